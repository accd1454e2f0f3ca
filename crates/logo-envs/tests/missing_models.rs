//! Its own test binary: it points LOGO_MODELS_DIR at an empty folder for the whole process.

#[test]
fn a_missing_model_names_the_setup_command() {
    let empty = std::env::temp_dir().join(format!("logo-no-models-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    // SAFETY: this test binary has no other test, so no thread reads the environment meanwhile.
    unsafe { std::env::set_var("LOGO_MODELS_DIR", &empty) };
    let err = logo_envs::make("Hopper-v4")
        .err()
        .expect("no model file, no env")
        .to_string();
    assert!(
        err.contains("hopper.xml") && err.contains("./scripts/setup.sh"),
        "{err}"
    );
}
