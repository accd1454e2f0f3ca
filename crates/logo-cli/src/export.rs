//! `logo export`: a checkpoint's policy alone, the form a run is kept in for the docs.
//! The policy's tensors and the observation statistics, bit for bit, with the metadata
//! that `logo eval` and `logo_rl.load` read (env, sizes, config, engine history); no
//! critics, discriminator or resume state, so the file is a fraction of the learner's and
//! `logo train --resume` refuses it by name.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use logo_nn::Checkpoint;

#[derive(Args)]
pub struct ExportArgs {
    /// A checkpoint (`checkpoint.safetensors`, `best.safetensors`) or a `logo bc` policy.
    #[arg(long)]
    checkpoint: PathBuf,
    /// Where the policy goes.
    #[arg(
        long,
        conflicts_with = "in_place",
        required_unless_present = "in_place"
    )]
    out: Option<PathBuf>,
    /// Replace the checkpoint by its policy (written beside it, then renamed over it).
    #[arg(long)]
    in_place: bool,
}

pub fn run(args: &ExportArgs) -> Result<()> {
    // clap asks for one of --out and --in-place; without --out it is the checkpoint.
    let out = args.out.clone().unwrap_or_else(|| args.checkpoint.clone());
    let (before, after) = export(&args.checkpoint, &out)?;
    println!(
        "{} -> {}: the policy alone, {} -> {} bytes",
        args.checkpoint.display(),
        out.display(),
        before,
        after
    );
    Ok(())
}

/// Writes `from`'s policy alone to `to` (which may be `from`); returns both sizes.
pub fn export(from: &Path, to: &Path) -> Result<(u64, u64)> {
    let size = |p: &Path| std::fs::metadata(p).map(|m| m.len());
    let before = size(from).with_context(|| from.display().to_string())?;
    let mut ckpt = Checkpoint::load(from)?;
    if !ckpt.meta.networks.contains_key("policy") {
        bail!("{}: the metadata lists no policy network", from.display());
    }
    let name = from
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    ckpt.make_policy_alone(&name);
    ckpt.save(to)?;
    Ok((before, size(to).with_context(|| to.display().to_string())?))
}
