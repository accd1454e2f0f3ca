//! `logo bc` and `[init] kind = "bc"` as a user meets them: BC on the LOGO IDP
//! demonstrations writes a checkpoint that `logo eval` scores and a run starts from, and
//! a BC-TRPO config clones before its first iteration.

use std::path::Path;

use logo_nn::Checkpoint;
use logo_testkit::{Logo, one_line_error, scratch, workspace};

fn cli() -> Logo {
    Logo::new(env!("CARGO_BIN_EXE_logo"))
}

fn idp_demos() -> String {
    workspace()
        .join("data/logo/inverted_double_pendulum")
        .display()
        .to_string()
}

fn policy_tensors(path: &Path) -> Vec<f64> {
    let ckpt = Checkpoint::load(path).unwrap();
    let mut names: Vec<&str> = ckpt
        .tensor_names()
        .filter(|n| n.starts_with("policy."))
        .collect();
    names.sort();
    names
        .iter()
        .flat_map(|n| ckpt.tensor(n).unwrap().1.to_vec())
        .collect()
}

#[test]
fn bc_writes_a_policy_that_eval_scores_and_a_run_starts_from() {
    let dir = scratch("bc");
    let out = dir.join("bc.safetensors");
    let printed = cli().succeed(&[
        "bc",
        "--env",
        "SparseInvertedDoublePendulum-v4",
        "--demos",
        &idp_demos(),
        "--epochs",
        "5",
        "--hidden",
        "16,16",
        "--episodes",
        "3",
        "--success",
        "none",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(printed.contains("behaviour cloning on"), "{printed}");
    assert!(printed.contains("evaluation, 3 episodes"), "{printed}");
    let ckpt = Checkpoint::load(&out).unwrap();
    assert_eq!(ckpt.meta.algorithm, "bc");
    assert_eq!(ckpt.meta.networks["policy"], vec![16, 16]);
    let report = &ckpt.meta.extra["bc"];
    assert!(report["loss_after"].as_f64().unwrap() < report["loss_before"].as_f64().unwrap());

    let scored = cli().succeed(&[
        "eval",
        "--checkpoint",
        out.to_str().unwrap(),
        "--episodes",
        "2",
    ]);
    assert!(
        scored.contains("SparseInvertedDoublePendulum-v4"),
        "{scored}"
    );
    assert!(scored.contains("(bc iteration 0"), "{scored}");

    // The evaluation kept beside the checkpoint is a run's eval.json for one policy: the
    // episodes `logo eval --json` plays from the same fresh states, judged by --success.
    let kept: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("bc.eval.json")).unwrap()).unwrap();
    let final_ = &kept["policies"]["final"];
    assert_eq!(final_["checkpoint"], "bc.safetensors");
    assert_eq!(
        final_["mean_action"]["summary"]["success_rate"],
        serde_json::Value::Null
    );
    let json = cli().succeed(&["eval", "--checkpoint", out.to_str().unwrap(), "--json"]);
    let played: serde_json::Value = serde_json::from_str(&json).unwrap();
    let returns = |episodes: &serde_json::Value| -> Vec<f64> {
        let list = episodes["mean_action"]["episodes"].as_array().unwrap();
        list.iter().map(|e| e["return"].as_f64().unwrap()).collect()
    };
    let (kept_returns, played_returns) = (returns(final_), returns(&played));
    assert_eq!(kept_returns.len(), 3);
    assert_eq!(kept_returns[..], played_returns[..3]);

    // A TRPO run from it: before its first step, the policy is BC's.
    let config = dir.join("trpo.toml");
    std::fs::write(
        &config,
        format!(
            "env = \"SparseInvertedDoublePendulum-v4\"\niterations = 1\nsamples_per_iter = 200\n\
             policy_hidden = [16, 16]\neval_steps = 50\ncheckpoint_every = 1\n\
             init_policy = {:?}\n[critic]\nhidden = [16, 16]\n",
            out.display().to_string()
        ),
    )
    .unwrap();
    let run = dir.join("run");
    cli().train(&config, &run, &["--iterations", "1"]);
    let trained = policy_tensors(&run.join("checkpoint.safetensors"));
    let cloned = policy_tensors(&out);
    assert_eq!(trained.len(), cloned.len());
    // One TRPO step (KL ≤ 0.01) moves the policy a little, not back to a random one.
    let gap = trained
        .iter()
        .zip(&cloned)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(gap > 0.0 && gap < 0.5, "largest change {gap}");
}

#[test]
fn a_bc_trpo_config_clones_before_its_first_iteration() {
    let dir = scratch("bc-trpo");
    let config = dir.join("bc_trpo.toml");
    let text = format!(
        "env = \"SparseInvertedDoublePendulum-v4\"\niterations = 1\nsamples_per_iter = 200\n\
         policy_hidden = [16, 16]\neval_steps = 50\n[critic]\nhidden = [16, 16]\n\
         [init]\nkind = \"bc\"\ndemos = {:?}\nepochs = 5\n",
        idp_demos()
    );
    std::fs::write(&config, &text).unwrap();
    let run = dir.join("run");
    let printed = cli().train(&config, &run, &[]);
    assert!(
        printed.contains("started from behaviour cloning on"),
        "{printed}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("bc.json")).unwrap()).unwrap();
    assert!(report["loss_after"].as_f64().unwrap() < report["loss_before"].as_f64().unwrap());
    // The stored config keeps [init], so the run can be made again.
    let stored = std::fs::read_to_string(run.join("config.toml")).unwrap();
    assert!(
        stored.contains("[init]") && stored.contains("kind = \"bc\""),
        "{stored}"
    );
    // The same config twice: the same numbers (BC draws from the run's seed).
    let again = dir.join("again");
    cli().train(&config, &again, &[]);
    assert_eq!(
        policy_tensors(&run.join("checkpoint.safetensors")),
        policy_tensors(&again.join("checkpoint.safetensors"))
    );

    // The clone is what the run starts from: without [init] the same config and seed
    // train other tensors (a clone fitted and then dropped would leave them equal).
    let plain = dir.join("plain.toml");
    // [init] is the config's last table, so the text before it is the config without it.
    std::fs::write(&plain, text.split("[init]").next().unwrap()).unwrap();
    let trpo = dir.join("trpo");
    cli().train(&plain, &trpo, &[]);
    assert_ne!(
        policy_tensors(&run.join("checkpoint.safetensors")),
        policy_tensors(&trpo.join("checkpoint.safetensors"))
    );
}

#[test]
fn bad_bc_settings_are_errors_naming_them() {
    let dir = scratch("bc-bad");
    let e = one_line_error(&cli().run(&[
        "bc",
        "--env",
        "SparseInvertedDoublePendulum-v4",
        "--demos",
        &idp_demos(),
        "--epochs",
        "0",
    ]));
    assert!(e.contains("--epochs must be at least 1"), "{e}");
    let e = one_line_error(&cli().run(&[
        "bc",
        "--env",
        "SparseHopper-v4",
        "--demos",
        &idp_demos(),
        "--out",
        dir.join("x.safetensors").to_str().unwrap(),
    ]));
    assert!(e.contains("inverted_double_pendulum"), "{e}");
    // [init] kind = "bc" with no demonstrations anywhere.
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        "env = \"SparseInvertedDoublePendulum-v4\"\niterations = 1\nsamples_per_iter = 200\n\
         [init]\nkind = \"bc\"\n",
    )
    .unwrap();
    let e = cli().train_error(&config, &dir.join("r"));
    assert!(e.contains("c.toml") && e.contains("init.demos"), "{e}");
    // An init_policy beside kind = "bc".
    std::fs::write(
        &config,
        format!(
            "env = \"SparseInvertedDoublePendulum-v4\"\niterations = 1\nsamples_per_iter = 200\n\
             init_policy = {:?}\n[init]\nkind = \"bc\"\ndemos = {:?}\n",
            config.display().to_string(),
            idp_demos()
        ),
    )
    .unwrap();
    let e = cli().train_error(&config, &dir.join("r2"));
    assert!(e.contains("init_policy"), "{e}");
}

#[test]
fn algorithms_lists_figure_1_and_the_seed_variants() {
    let listed = cli().succeed(&["algorithms"]);
    // The LOGO paper's Figure 1 methods, BC, and the seed paper's variants.
    let names = [
        "trpo",
        "bc",
        "bc-trpo",
        "gail",
        "pofd",
        "dapg",
        "logo",
        "logo-ppo",
        "logo-cdq",
        "logo-ppo-cdq",
        "logo-clip-in-trpo",
        "logo-ppo-penalty",
    ];
    for name in names {
        assert!(
            listed.lines().any(|l| l.starts_with(&format!("{name} "))),
            "{name} missing from:\n{listed}"
        );
    }
}
