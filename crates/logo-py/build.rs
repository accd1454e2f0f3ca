//! The extension's MuJoCo is the `mujoco` wheel's libmujoco.so.3.17.0, which
//! `logo_rl/__init__.py` loads before it. The rpath below
//! (site-packages/logo_rl/ → site-packages/mujoco/) also finds it for a build installed
//! from source; the distribution wheel drops both it and the library's name from its link
//! table (scripts/unlink_mujoco.py).
//!
//! It also carries the repository's training configs as presets, with the demonstration
//! datasets they name, so that `logo_rl.train("new-task", ...)` needs no repository: this
//! script lists them into `$OUT_DIR/presets.rs` (`include_str!`/`include_bytes!` of the
//! files themselves, so there is one copy of each, in `configs/` and `data/`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The table of methods, read for the folders of configs it names.
#[path = "../logo-algo/src/methods.rs"]
#[allow(dead_code)]
mod methods;

/// The config folders that become presets ("<folder>/<stem>"; templates/new_task.toml is
/// "new-task"): the templates, each method's that runs as a config, LOGO as the
/// reference code computes it.
fn folders() -> Vec<&'static str> {
    let methods = methods::METHODS.iter().filter(|m| m.command.is_none());
    std::iter::once("templates")
        .chain(methods.map(|m| m.name))
        .chain(["reference"])
        .collect()
}

fn main() {
    println!("cargo::rustc-link-arg-cdylib=-Wl,-rpath,$ORIGIN/../mujoco");
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let root = root.canonicalize().expect("the repository root");
    let mut presets = String::new();
    let mut data: Vec<String> = Vec::new();
    println!("cargo::rerun-if-changed=../logo-algo/src/methods.rs");
    for folder in folders() {
        let dir = root.join("configs").join(folder);
        println!("cargo::rerun-if-changed={}", dir.display());
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|entry| entry.expect("a folder entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        files.sort();
        for file in files {
            println!("cargo::rerun-if-changed={}", file.display());
            let text = std::fs::read_to_string(&file).expect("a config");
            let stem = file.file_stem().unwrap().to_string_lossy();
            let name = if folder == "templates" {
                stem.replace('_', "-")
            } else {
                format!("{folder}/{stem}")
            };
            let relative = format!("configs/{folder}/{stem}.toml");
            for demos in named_paths(&text) {
                let target = dir
                    .join(&demos)
                    .canonicalize()
                    .unwrap_or_else(|e| panic!("{}: demos = {demos:?}: {e}", file.display()));
                for path in files_under(&target) {
                    let inside = path
                        .strip_prefix(&root)
                        .expect("data inside the repository");
                    let inside = inside.to_string_lossy().into_owned();
                    if !data.contains(&inside) {
                        data.push(inside);
                    }
                }
            }
            writeln!(
                presets,
                "    ({name:?}, {relative:?}, {about:?}, include_str!({path:?})),",
                about = about(&text),
                path = file.display().to_string(),
            )
            .unwrap();
        }
    }
    let mut out = String::from(
        "/// (name, path in the repository, what it is, the config's text).\n\
         pub const PRESETS: &[(&str, &str, &str, &str)] = &[\n",
    );
    out.push_str(&presets);
    out.push_str("];\n\n/// The files the presets name: (path in the repository, bytes).\n");
    out.push_str("pub const PRESET_DATA: &[(&str, &[u8])] = &[\n");
    for inside in &data {
        let path = root.join(inside);
        println!("cargo::rerun-if-changed={}", path.display());
        writeln!(
            out,
            "    ({inside:?}, include_bytes!({:?})),",
            path.display().to_string()
        )
        .unwrap();
    }
    out.push_str("];\n");
    let target = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("presets.rs");
    std::fs::write(target, out).expect("OUT_DIR/presets.rs");
}

/// The values of `demos = "..."` and `behaviour_policy = "..."` lines.
fn named_paths(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|line| {
            let (key, value) = line.split_once('=')?;
            let key = key.trim();
            if key != "demos" && key != "behaviour_policy" && key != "init_policy" {
                return None;
            }
            Some(
                value
                    .split('#')
                    .next()?
                    .trim()
                    .trim_matches('"')
                    .to_string(),
            )
        })
        .collect()
}

/// The config's opening comment up to its first full stop or bracket (at most about 100
/// characters).
fn about(text: &str) -> String {
    let comment: Vec<&str> = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| l.trim_start_matches('#').trim())
        .collect();
    let joined = comment.join(" ");
    let end = [". ", " ("]
        .iter()
        .filter_map(|mark| joined.find(mark))
        .min()
        .unwrap_or(joined.len());
    let sentence = joined[..end].trim_end_matches('.');
    if sentence.chars().count() <= 100 {
        return sentence.to_string();
    }
    let cut: String = sentence.chars().take(100).collect();
    format!("{}…", &cut[..cut.rfind(' ').unwrap_or(cut.len())])
}

/// Every file under `path` (itself if a file), sorted.
fn files_under(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_path_buf()];
    }
    let mut out = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .map(|entry| entry.expect("a folder entry").path())
        .collect();
    entries.sort();
    for entry in entries {
        out.extend(files_under(&entry));
    }
    out
}
