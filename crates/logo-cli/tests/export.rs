//! `logo export`: a learner's checkpoint made into its policy alone, the form the docs keep
//! runs in. The policy plays the same episodes, holds nothing but the policy and the
//! observation statistics, and `logo train --resume` refuses it by name.

use std::path::{Path, PathBuf};

use logo_nn::Checkpoint;
use logo_testkit::{Logo, TINY_LOGO_TEXT, one_line_error, scratch, write_demos_npy};

fn cli() -> Logo {
    Logo::new(env!("CARGO_BIN_EXE_logo"))
}

/// A tiny LOGO run with standardised observations, trained here: its checkpoint holds
/// critics, a discriminator, the observation statistics and a resume state.
fn logo_run(name: &str) -> PathBuf {
    let dir = scratch(name);
    write_demos_npy(&dir.join("demos.npy"), 200, 12);
    let config = dir.join("logo.toml");
    std::fs::write(
        &config,
        format!("normalise_observations = true\n{TINY_LOGO_TEXT}"),
    )
    .unwrap();
    let run = dir.join("run");
    cli().train(&config, &run, &["--no-tensorboard"]);
    run
}

fn tensors_under(ckpt: &Checkpoint, prefixes: &[&str]) -> Vec<(String, Vec<f64>)> {
    ckpt.tensor_names()
        .filter(|n| prefixes.iter().any(|p| n.starts_with(p)))
        .map(|n| (n.to_string(), ckpt.tensor(n).unwrap().1.to_vec()))
        .collect()
}

/// `logo export --checkpoint CHECKPOINT` and `rest`, as arguments.
fn export<'a>(checkpoint: &'a Path, rest: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["export", "--checkpoint", checkpoint.to_str().unwrap()];
    args.extend_from_slice(rest);
    args
}

/// `logo eval --json`'s episodes, without the line naming the file.
fn episodes(path: &Path) -> String {
    cli()
        .succeed(&[
            "eval",
            "--checkpoint",
            path.to_str().unwrap(),
            "--json",
            "--episodes",
            "20",
        ])
        .lines()
        .filter(|line| !line.contains("\"checkpoint\""))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn an_exported_policy_is_the_policy_alone_and_plays_the_same_episodes() {
    let from = logo_run("export").join("checkpoint.safetensors");
    let dir = from.parent().unwrap().to_path_buf();
    let out = dir.join("policy.safetensors");
    let printed = cli().succeed(&export(&from, &["--out", out.to_str().unwrap()]));
    assert!(printed.contains("the policy alone"), "{printed}");

    let (before, after) = (
        Checkpoint::load(&from).unwrap(),
        Checkpoint::load(&out).unwrap(),
    );
    let kept = ["policy.", "observation_norm."];
    for network in ["critic.", "guidance_critic.", "discriminator."] {
        assert!(
            before.tensor_names().any(|n| n.starts_with(network)),
            "the run's checkpoint holds {network}*"
        );
    }
    assert!(!before.meta.extra["resume"].is_null());
    assert!(!tensors_under(&before, &["observation_norm."]).is_empty());
    // Bit for bit, and nothing else.
    assert_eq!(tensors_under(&before, &kept), tensors_under(&after, &kept));
    assert_eq!(
        after.tensor_names().count(),
        tensors_under(&after, &kept).len()
    );
    assert_eq!(
        after.meta.networks.keys().collect::<Vec<_>>(),
        ["policy"],
        "networks listed: {:?}",
        after.meta.networks
    );
    assert!(after.meta.extra["resume"].is_null());
    assert_eq!(after.meta.extra["config"], before.meta.extra["config"]);
    assert_eq!(after.meta.extra["engines"], before.meta.extra["engines"]);
    assert_eq!(
        after.meta.extra["exported"]["from"],
        "checkpoint.safetensors"
    );
    assert_eq!(
        (
            after.meta.env_id.as_str(),
            after.meta.iteration,
            after.meta.seed
        ),
        (
            before.meta.env_id.as_str(),
            before.meta.iteration,
            before.meta.seed
        )
    );
    let (size_before, size_after) = (
        std::fs::metadata(&from).unwrap().len(),
        std::fs::metadata(&out).unwrap().len(),
    );
    assert!(
        size_after * 5 < size_before,
        "{size_before} -> {size_after}"
    );

    // The same 20 episodes, action for action, as the learner's checkpoint plays.
    assert_eq!(episodes(&from), episodes(&out));

    // Exporting an exported policy changes nothing: it keeps the mark of the file it
    // first came from.
    let again = dir.join("again.safetensors");
    cli().succeed(&export(&out, &["--out", again.to_str().unwrap()]));
    assert_eq!(Checkpoint::load(&again).unwrap().meta, after.meta);
}

#[test]
fn in_place_replaces_the_checkpoint_and_resume_refuses_it_by_name() {
    let dir = logo_run("export-in-place");
    let path = dir.join("checkpoint.safetensors");
    cli().succeed(&export(&path, &["--in-place"]));
    assert!(
        Checkpoint::load(&path)
            .unwrap()
            .tensor_names()
            .all(|n| n.starts_with("policy.") || n.starts_with("observation_norm."))
    );
    let err = one_line_error(&cli().run(&["train", "--resume", dir.to_str().unwrap()]));
    assert!(
        err.contains("is a policy alone (`logo export`)")
            && err.contains(&path.display().to_string()),
        "{err}"
    );
}

#[test]
fn export_mistakes_are_answered_in_one_line() {
    let dir = scratch("export-mistakes");
    let missing = dir.join("none.safetensors");
    let out = dir.join("p.safetensors");
    let err = one_line_error(&cli().run(&export(&missing, &["--out", out.to_str().unwrap()])));
    assert!(err.contains("none.safetensors"), "{err}");
    let not_one = dir.join("text.safetensors");
    std::fs::write(&not_one, "not a checkpoint").unwrap();
    let err = one_line_error(&cli().run(&export(&not_one, &["--in-place"])));
    assert!(
        err.contains("text.safetensors") && err.contains("not a safetensors file"),
        "{err}"
    );
    assert_eq!(std::fs::read(&not_one).unwrap(), b"not a checkpoint");
    // Neither --out nor --in-place: clap names what is missing.
    let out = cli().run(&export(&not_one, &[]));
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--out"));
}
