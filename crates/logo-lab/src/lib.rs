//! The lab tools of the `logo` binary, apart from training: reading run folders
//! ([`runs`]), `logo summary`'s tables with bootstrap intervals ([`summary`]) and `logo
//! plot`'s figures ([`plot`]). They read what runs leave on disk (metrics.csv,
//! config.toml, eval.json) and depend on no engine or trainer.

pub mod plot;
pub mod runs;
pub mod summary;
