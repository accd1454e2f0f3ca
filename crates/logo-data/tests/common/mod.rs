//! Helpers shared by the data tests: scratch folders and the Python (minari, h5py) oracle.
#![allow(dead_code)]

pub mod corrupt;

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("logo-data-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn python() -> Option<PathBuf> {
    let python = repo().join(".venv/bin/python");
    let has_minari = python.exists()
        && Command::new(&python)
            .args(["-c", "import minari, h5py"])
            .status()
            .is_ok_and(|s| s.success());
    if has_minari {
        return Some(python);
    }
    assert!(
        std::env::var_os("LOGO_REQUIRE_PYTHON").is_none(),
        "{} with minari is missing: run ./scripts/setup.sh",
        python.display()
    );
    eprintln!("skipped: no Python with minari");
    None
}

/// Runs `tests/python/minari_roundtrip.py` with `args`; its stdout.
pub fn script(python: &Path, args: &[&str]) -> String {
    let out = Command::new(python)
        .arg(repo().join("tests/python/minari_roundtrip.py"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}
