//! Observers that write: the Rerun recording, the CSV time series and the JSON summary, plus
//! the run driver that hangs them off a [`crate::Simulation`].

pub mod bench3d;
pub mod breaker_map;
pub mod colormap;
pub mod recorder;
pub mod rrd;
pub mod rrd3d;
pub mod run;
pub mod run3d;
pub mod summary;
pub mod surf;
pub mod timeseries;
