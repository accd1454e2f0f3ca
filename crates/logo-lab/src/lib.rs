//! The lab tools of the `logo` binary, apart from training and evaluating: reading run
//! folders ([`runs`]), `logo summary`'s tables with bootstrap intervals ([`summary`]),
//! `logo plot`'s figures ([`plot`]), `logo compare`'s reports ([`compare`]), `logo sweep`'s plans run locally or on Slurm
//! ([`sweep`]) and `logo bench`'s measurements ([`bench`]). Plot, summary and runs read
//! only what runs leave on disk (metrics.csv, config.toml, eval.json); sweep runs
//! `logo train` for each run, and bench times the envs, the networks and the trainer.

pub mod bench;
pub mod compare;
pub mod plot;
pub mod runs;
pub mod summary;
pub mod sweep;
