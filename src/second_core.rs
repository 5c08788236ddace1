//! The step's second core: one thread kept for the life of a solver, which runs the parts of
//! a step that go in parallel (one piece of the Delaunay triangulation, the symbolic Cholesky
//! analysis) and hands back their results.
//!
//! Why not a new thread per job: on the 2-core VMs this project runs on, a freshly spawned
//! thread started its work 0.87 ms after the call (mean over 1 500 steps of the teaching
//! beach; 1.8 ms in a bare loop), so the symbolic analysis, 1.2 ms of work, was ready 2.1 ms
//! after the call and the main thread waited 1.2 ms of each 10 ms step for it. A job sent to a
//! thread that is already running starts about 10 µs after the call.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

type Job = Box<dyn FnOnce() + Send>;

/// A persistent worker thread; jobs run one at a time in the order sent.
pub struct SecondCore {
    jobs: Option<Sender<Job>>,
    thread: Option<JoinHandle<()>>,
}

/// The result of a job sent to the second core, to be waited for.
pub struct Pending<T>(Receiver<std::thread::Result<T>>);

impl SecondCore {
    /// Starts the thread; `None` if the system refuses one (the caller then works serially).
    pub fn start() -> Option<SecondCore> {
        let (jobs, queue) = channel::<Job>();
        let thread = std::thread::Builder::new()
            .name("surflab-second-core".into())
            .spawn(move || {
                for job in queue {
                    job();
                }
            })
            .ok()?;
        Some(SecondCore {
            jobs: Some(jobs),
            thread: Some(thread),
        })
    }

    /// Runs `f` on the second core. A panic in `f` is caught and returned by
    /// [`Pending::wait`]; the thread lives on.
    pub fn run<T: Send + 'static>(&self, f: impl FnOnce() -> T + Send + 'static) -> Pending<T> {
        let (result, receiver) = channel();
        let job: Job = Box::new(move || {
            // The receiver may be gone (its step failed before waiting); nothing to tell then.
            let _ = result.send(catch_unwind(AssertUnwindSafe(f)));
        });
        if let Some(jobs) = &self.jobs
            && let Err(returned) = jobs.send(job)
        {
            // The thread is gone (it cannot panic out of its loop, but be safe): run here.
            (returned.0)();
        }
        Pending(receiver)
    }
}

impl<T> Pending<T> {
    /// Waits for the job; `Err` with the panic's payload if it panicked.
    pub fn wait(self) -> std::thread::Result<T> {
        self.0
            .recv()
            .unwrap_or_else(|_| Err(Box::new("the second core dropped the job")))
    }
}

impl Drop for SecondCore {
    fn drop(&mut self) {
        // Closing the queue ends the thread's loop once the jobs sent have run.
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl std::fmt::Debug for SecondCore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SecondCore")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_return_their_results_in_order_and_a_panic_is_caught() {
        let core = SecondCore::start().expect("a thread");
        let a = core.run(|| 2 + 2);
        let b = core.run(|| -> i32 { panic!("a job that fails") });
        let c = core.run(|| vec![1u8; 3]);
        assert_eq!(a.wait().unwrap(), 4);
        assert!(b.wait().is_err());
        // The thread survived the panic.
        assert_eq!(c.wait().unwrap(), vec![1, 1, 1]);
        assert_eq!(core.run(|| "still here").wait().unwrap(), "still here");
    }
}
