//! Fails the build with one line naming the fix when MuJoCo was never installed.
//! (mujoco-rs itself only sees the committed linker script `libmujoco.so`.)
use std::path::PathBuf;

fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR") else {
        return; // the user links MuJoCo some other way (pkg-config, static)
    };
    let lib = PathBuf::from(&dir).join("libmujoco.so.3.17.0");
    println!("cargo::rerun-if-changed={}", lib.display());
    if !lib.is_file() {
        panic!(
            "MuJoCo 3.17.0 is not installed ({} is missing): run ./scripts/setup.sh",
            lib.display()
        );
    }
}
