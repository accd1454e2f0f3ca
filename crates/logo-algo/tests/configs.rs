//! Every config under configs/ loads, names a real env, and its demonstrations fit it.

use std::path::Path;

use logo_algo::TrainConfig;
use logo_data::Demonstrations;
use logo_envs::{EnvFactory, EnvOptions};

#[test]
fn every_shipped_config_loads_and_its_demos_fit_the_env() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut checked = 0;
    for algo in ["logo", "trpo", "behaviour"] {
        for entry in std::fs::read_dir(root.join("configs").join(algo)).unwrap() {
            let path = entry.unwrap().path();
            let config = TrainConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let spec = EnvFactory::new(&config.env, &EnvOptions::default())
                .unwrap()
                .spec()
                .clone();
            EnvFactory::new(&config.eval_env_id(), &EnvOptions::default()).unwrap();
            assert_eq!(
                config.guidance.is_some(),
                algo == "logo",
                "{}",
                path.display()
            );
            if let Some(demos) = config.guidance.as_ref().and_then(|g| g.demos.as_ref()) {
                let d = Demonstrations::load(demos, spec.obs_dim, spec.act_dim)
                    .unwrap_or_else(|e| panic!("{e}"));
                assert!(d.len() > 100, "{}", path.display());
            }
            checked += 1;
        }
    }
    assert_eq!(
        checked, 10,
        "four tasks, LOGO and TRPO; the Hopper behaviour pipeline and LOGO from its set"
    );
}
