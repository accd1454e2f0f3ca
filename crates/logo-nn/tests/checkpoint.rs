//! Checkpoints: bit-exact round trips, errors that name the tensor, no panics on bad files.

use std::process::Command;

use burn::module::Module;
use logo_nn::flat::{params_to_vec, vec_to_params};
use logo_nn::{
    Checkpoint, CheckpointError, CheckpointMeta, Cpu, Cpu32, DiscriminatorConfig, PolicyConfig,
    ValueNetConfig,
};
use logo_testkit::scratch;

fn meta() -> CheckpointMeta {
    let mut meta = CheckpointMeta::new("SparseHopper-v4", 11, 3, "logo");
    meta.networks.insert("policy".into(), vec![128, 128]);
    meta.iteration = 42;
    meta.seed = 7;
    meta.extra = serde_json::json!({"obs_mean": [0.1, 0.2]});
    meta
}

#[test]
fn float64_round_trips_bit_exactly_with_metadata() {
    let device = Default::default();
    let policy = PolicyConfig::new(11, 3).init::<Cpu>(&device);
    // Values with full mantissas, so a lossy path would show.
    let theta: Vec<f64> = (0..policy.num_params())
        .map(|i| (i as f64 * 0.7311).sin() / 3.0)
        .collect();
    let policy = vec_to_params(policy, &theta);
    let critic: Vec<_> = (0..2)
        .map(|_| ValueNetConfig::new(11).init::<Cpu>(&device))
        .collect();
    let disc = DiscriminatorConfig::new(7, 3).init::<Cpu>(&device);

    let mut ckpt = Checkpoint::new(meta());
    ckpt.insert("policy", &policy);
    ckpt.insert("critic", &critic);
    ckpt.insert("discriminator", &disc);
    let path = scratch("roundtrip").join("run/ckpt.safetensors");
    ckpt.save(&path).unwrap();
    assert_eq!(
        std::fs::read_dir(path.parent().unwrap()).unwrap().count(),
        1,
        "no temporary file left behind"
    );

    let loaded = Checkpoint::load(&path).unwrap();
    assert_eq!(loaded.meta, meta());
    let fresh = PolicyConfig::new(11, 3).init::<Cpu>(&device);
    let restored = loaded.apply("policy", fresh).unwrap();
    let back = params_to_vec(&restored);
    assert!(
        back.iter()
            .zip(&theta)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    let critic2 = loaded
        .apply(
            "critic",
            (0..2)
                .map(|_| ValueNetConfig::new(11).init::<Cpu>(&device))
                .collect::<Vec<_>>(),
        )
        .unwrap();
    assert_eq!(params_to_vec(&critic2), params_to_vec(&critic));
    let disc2 = loaded
        .apply(
            "discriminator",
            DiscriminatorConfig::new(7, 3).init::<Cpu>(&device),
        )
        .unwrap();
    assert_eq!(params_to_vec(&disc2), params_to_vec(&disc));
    assert!(
        loaded
            .tensor_names()
            .any(|n| n == "policy.mean.layers.0.weight")
    );
    assert!(
        loaded
            .tensor_names()
            .any(|n| n == "critic.1.net.layers.2.bias")
    );

    // Saving again over the same path replaces it.
    let mut again = Checkpoint::new(CheckpointMeta {
        iteration: 43,
        ..meta()
    });
    again.insert("policy", &restored);
    again.save(&path).unwrap();
    assert_eq!(Checkpoint::load(&path).unwrap().meta.iteration, 43);
}

#[test]
fn float32_networks_round_trip_exactly() {
    let device = Default::default();
    let policy = PolicyConfig::new(5, 2).init::<Cpu32>(&device);
    let mut ckpt = Checkpoint::new(meta());
    ckpt.insert("policy", &policy);
    let path = scratch("f32").join("p.safetensors");
    ckpt.save(&path).unwrap();
    let back = Checkpoint::load(&path)
        .unwrap()
        .apply("policy", PolicyConfig::new(5, 2).init::<Cpu32>(&device))
        .unwrap();
    assert_eq!(params_to_vec(&back), params_to_vec(&policy));
}

#[test]
fn a_mismatched_network_gets_an_error_naming_the_tensor_and_dims() {
    let device = Default::default();
    let mut ckpt = Checkpoint::new(meta());
    ckpt.insert("policy", &PolicyConfig::new(11, 3).init::<Cpu>(&device));
    let path = scratch("shape").join("p.safetensors");
    ckpt.save(&path).unwrap();
    let loaded = Checkpoint::load(&path).unwrap();

    let err = loaded
        .apply("policy", PolicyConfig::new(17, 3).init::<Cpu>(&device))
        .unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, CheckpointError::Shape { .. }), "{text}");
    assert!(
        text.contains("policy.mean.layers.0.weight")
            && text.contains("[11, 128]")
            && text.contains("[17, 128]"),
        "{text}"
    );
    assert!(text.contains("p.safetensors"), "{text}");

    let err = loaded
        .apply("critic", ValueNetConfig::new(11).init::<Cpu>(&device))
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("critic.net.layers.0.weight is missing"),
        "{err}"
    );

    let small = PolicyConfig {
        hidden: vec![128],
        ..PolicyConfig::new(11, 3)
    };
    let err = loaded
        .apply("policy", small.init::<Cpu>(&device))
        .unwrap_err();
    assert!(
        matches!(
            err,
            CheckpointError::Shape { .. } | CheckpointError::Unexpected { .. }
        ),
        "{err}"
    );
}

#[test]
fn corrupted_and_truncated_files_are_errors_not_panics() {
    let device = Default::default();
    let mut ckpt = Checkpoint::new(meta());
    ckpt.insert("policy", &PolicyConfig::new(11, 3).init::<Cpu>(&device));
    let dir = scratch("corrupt");
    let good = dir.join("good.safetensors");
    ckpt.save(&good).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let bad = dir.join("bad.safetensors");
    // Every truncation length in the header region and a spread over the data, plus
    // single flipped bytes.
    let mut cases: Vec<Vec<u8>> = (0..200.min(bytes.len()))
        .map(|n| bytes[..n].to_vec())
        .collect();
    cases.extend((0..bytes.len()).step_by(997).map(|n| bytes[..n].to_vec()));
    for i in (0..bytes.len()).step_by(131) {
        let mut flipped = bytes.clone();
        flipped[i] ^= 0xA5;
        cases.push(flipped);
    }
    cases.push(b"not a checkpoint at all".to_vec());
    let mut errors = 0;
    for case in &cases {
        std::fs::write(&bad, case).unwrap();
        match Checkpoint::load(&bad) {
            Err(e) => {
                assert!(e.to_string().contains("bad.safetensors"), "{e}");
                errors += 1;
            }
            Ok(c) => {
                // A flipped byte inside the data can leave a valid file: then the values
                // are finite and the names still check on apply, or it errs there.
                let _ = c.apply("policy", PolicyConfig::new(11, 3).init::<Cpu>(&device));
            }
        }
    }
    assert!(
        errors > 200,
        "{errors} of {} corrupted files were rejected",
        cases.len()
    );
    let missing = Checkpoint::load(&dir.join("nope.safetensors")).unwrap_err();
    assert!(
        missing.to_string().contains("nope.safetensors"),
        "{missing}"
    );
}

/// The file opens in Python's `safetensors` (the README's promise to users of other tools).
/// Skipped only when the venv is absent and LOGO_REQUIRE_PYTHON is unset.
#[test]
fn python_safetensors_opens_a_checkpoint() {
    let Some(python) = logo_testkit::python() else {
        return;
    };
    let device = Default::default();
    let policy = PolicyConfig::new(11, 3).init::<Cpu>(&device);
    let theta = params_to_vec(&policy);
    let mut ckpt = Checkpoint::new(meta());
    ckpt.insert("policy", &policy);
    let path = scratch("python").join("p.safetensors");
    ckpt.save(&path).unwrap();
    let script = r#"
import json, sys
from safetensors import safe_open
with safe_open(sys.argv[1], "np") as f:
    meta = json.loads(f.metadata()["logo_rl"])
    w = f.get_tensor("policy.mean.layers.0.weight")
    print(meta["env_id"], meta["iteration"], w.dtype, w.shape[0], w.shape[1], repr(float(w[0, 1])))
"#;
    let out = Command::new(&python)
        .arg("-c")
        .arg(script)
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let fields: Vec<&str> = text.split_whitespace().collect();
    assert_eq!(
        &fields[..5],
        ["SparseHopper-v4", "42", "float64", "11", "128"]
    );
    assert_eq!(
        fields[5].parse::<f64>().unwrap().to_bits(),
        theta[1].to_bits()
    );
}

/// A read with no prefix owns every tensor of the file: one belonging to no part of the
/// module is refused, named, where a read under a prefix ignores what is outside it.
#[test]
fn a_whole_file_read_refuses_a_stray_tensor() {
    let device = Default::default();
    let policy = PolicyConfig::new(11, 3).init::<Cpu>(&device);
    let path = scratch("stray").join("ckpt.safetensors");
    for prefix in ["", "policy"] {
        let mut ckpt = Checkpoint::new(meta());
        ckpt.insert(prefix, &policy);
        ckpt.insert("stray", &ValueNetConfig::new(11).init::<Cpu>(&device));
        ckpt.save(&path).unwrap();
        let read = Checkpoint::load(&path)
            .unwrap()
            .apply(prefix, PolicyConfig::new(11, 3).init::<Cpu>(&device));
        if prefix.is_empty() {
            let err = read.unwrap_err().to_string();
            assert!(
                err.contains("stray.") && err.contains("belong to none of the networks"),
                "{err}"
            );
        } else {
            assert!(read.is_ok(), "under {prefix:?}");
        }
    }
}
