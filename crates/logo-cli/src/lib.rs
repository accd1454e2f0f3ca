//! The `logo` command's subcommands as a library: the binary (`main.rs`) parses the command
//! line and calls them; the Python package (`crates/logo-py`) calls the trainer's job and
//! the evaluation the same way, so a run from Python writes what `logo train` writes.

pub mod bc;
pub mod data;
pub mod eval;
pub mod export;
pub mod final_eval;
pub mod rollout;
pub mod train;
pub mod video;
