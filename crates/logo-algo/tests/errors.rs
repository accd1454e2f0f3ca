//! A run's errors are values a caller can act on: the variant says what kind of mistake
//! stopped it (a missing file, a refused value, a folder in use, a resume state that does
//! not fit), whatever places were put in front of it.

use std::io::ErrorKind;

use logo_algo::{At, Invalid, TrainConfig, TrainError, Trainer};
use logo_nn::Kernels;
use logo_testkit::{Tiny, scratch};

/// `Trainer::new` or `Trainer::resume`'s error (a trainer has no Debug to unwrap_err with).
fn refused<T>(result: Result<T, TrainError>) -> TrainError {
    match result {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

#[test]
fn a_runs_errors_say_their_kind() {
    let dir = scratch("errors");
    let config = |tiny: Tiny| TrainConfig::load(&tiny.write(&dir.join("config.toml"))).unwrap();

    // Nothing to resume: the checkpoint is a missing file.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let e = refused(Trainer::resume(Kernels, &empty, None));
    assert!(
        matches!(e.cause(), TrainError::Io { source, .. } if source.kind() == ErrorKind::NotFound),
        "{e:?}"
    );

    // A value the checks refuse, set after the file was read: a refused value, under
    // the place ("config") it was found.
    let mut bad = config(Tiny::trpo());
    bad.gamma = 2.0;
    let e = refused(Trainer::new(Kernels, bad, &dir.join("bad")));
    assert!(matches!(e, TrainError::At { .. }), "{e:?}");
    assert!(matches!(e.cause(), TrainError::Invalid(_)), "{e:?}");
    assert_eq!(e.to_string(), "config: gamma must be in [0, 1], got 2");

    // A folder that holds a run already.
    let run = dir.join("run");
    let mut trainer = Trainer::new(Kernels, config(Tiny::trpo()), &run).unwrap();
    trainer.step().unwrap();
    trainer
        .save_checkpoint(&run.join("checkpoint.safetensors"))
        .unwrap();
    drop(trainer);
    let e = refused(Trainer::new(Kernels, config(Tiny::trpo()), &run));
    assert!(matches!(e, TrainError::Busy(_)), "{e:?}");

    // A checkpoint whose metrics.csv is not its run's: the resume state does not fit.
    std::fs::write(run.join("metrics.csv"), "").unwrap();
    let e = refused(Trainer::resume(Kernels, &run, Some(3)));
    assert!(matches!(e.cause(), TrainError::Resume(_)), "{e:?}");
    assert!(e.to_string().contains("rows are missing"), "{e}");

    // A demonstrations file gone after the config was read: a missing file, as the
    // config's check says it (and the data's own error where the trainer reads it).
    let mut demos = config(Tiny::logo());
    demos.guidance.as_mut().unwrap().demos = Some(dir.join("absent.npy"));
    let e = refused(Trainer::new(Kernels, demos, &dir.join("demos")));
    assert!(
        matches!(e.cause(), TrainError::Invalid(Invalid::Missing(_))),
        "{e:?}"
    );
    let spec = spec();
    let gone = logo_data::Demonstrations::load(
        &dir.join("absent.npy"),
        &spec.id,
        spec.obs_dim,
        spec.act_dim,
    )
    .at("k");
    let e = gone.expect_err("no such file");
    let missing = match e.cause() {
        TrainError::Data(logo_data::DataError::Io { source, .. }) => source.kind(),
        other => panic!("{other:?}"),
    };
    assert_eq!(missing, ErrorKind::NotFound);
    assert!(e.to_string().starts_with("k: "), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Sparse IDP's spec, for a loader that checks demonstrations against it.
fn spec() -> logo_envs::EnvSpec {
    logo_envs::make("SparseInvertedDoublePendulum-v4")
        .unwrap()
        .spec()
        .clone()
}
