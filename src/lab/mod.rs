//! The lab (feature `lab`): one window with the Rerun viewer embedded in-process and our egui
//! side panel; the solver runs in a worker thread and streams into the viewer through an
//! in-process channel (no network port, no separate viewer).
//!
//! - [`controls`]: settings → case, and the derived read-outs (no egui);
//! - [`worker`]: the solver thread and its typed commands; [`pacer`]: how it shares the cores
//!   with the window;
//! - [`panel`]: the side panel;
//! - [`window`]: the eframe app that hosts the viewer and the panel;
//! - [`view`]: `surflab view`, recordings in the same embedded viewer.

pub mod controls;
pub mod pacer;
pub mod panel;
mod view;
mod window;
pub mod worker;

pub use view::{ViewOptions, view};
pub use window::{LabOptions, run};
