//! `cloth-sim`, the simulation process: `cloth-sim run` steps the design (the `sim-core`
//! library), follows the pen, answers the UI's commands, publishes what the haptic loop
//! and the UI need over iceoryx2, and autosaves. The headless scenarios of `cloth-sim
//! scenario` are the library's own (`sim_core::scenario`); `main.rs` is the command line.
//!
//! - `service`: the frame loop and the command server;
//! - `pen`: the pen's samples and what its button does with the current tool;
//! - `commands`: carrying out the UI's commands on the design;
//! - `publish`: the local model, the cloth, the body and the texture going out;
//! - `export`: the EXPORT command's files and `sim-report.json`;
//! - `autosave`: the autosave writer and resume;
//! - `config`: the service's settings and counters.

mod autosave;
mod commands;
mod config;
mod export;
mod pen;
mod publish;
mod service;

pub use autosave::{backup_of, prepare_dir, resume_or, start_fresh};
pub use commands::{carry_out, new_design, set_strain_limit};
pub use config::{ServiceConfig, ServiceStats};
pub use service::run;
