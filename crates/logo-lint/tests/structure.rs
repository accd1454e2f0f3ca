//! The rules over this repository's own tree, and checks that each rule can fail.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use logo_lint::{LONG_BY_DESIGN, LongFunction, ModuleGraph, display, long_functions};
use logo_testkit::workspace;

fn describe(cycles: &[Vec<logo_lint::Edge>]) -> String {
    let mut text = String::new();
    for (i, cycle) in cycles.iter().enumerate() {
        text.push_str(&format!("cycle {}:\n", i + 1));
        for edge in cycle {
            text.push_str(&format!(
                "  {} -> {}   ({})\n",
                display(&edge.from),
                display(&edge.to),
                edge.example
            ));
        }
    }
    text
}

#[test]
fn modules_of_every_crate_import_each_other_without_a_cycle() {
    let crates = workspace().join("crates");
    let mut report = String::new();
    let mut checked = 0;
    for entry in std::fs::read_dir(&crates).unwrap() {
        let dir = entry.unwrap().path();
        if !dir.join("Cargo.toml").is_file() {
            continue;
        }
        let name = dir.file_name().unwrap().to_string_lossy().to_string();
        let graph = ModuleGraph::load(&name, &dir.join("src")).unwrap();
        let cycles = graph.cycles();
        if !cycles.is_empty() {
            report.push_str(&format!("{name}:\n{}", describe(&cycles)));
        }
        checked += 1;
    }
    assert!(
        checked >= 6,
        "found only {checked} crates under {}",
        crates.display()
    );
    assert!(
        report.is_empty(),
        "modules that import each other:\n{report}"
    );
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn listing(long: &[&LongFunction]) -> String {
    let lines: Vec<String> = long
        .iter()
        .map(|f| {
            format!(
                "{}:{} {} ({} lines)",
                f.file.display(),
                f.line,
                f.name,
                f.lines
            )
        })
        .collect();
    lines.join("\n")
}

/// No function of any crate's own code (its `src/`, tests aside) is over 80 lines, unless
/// its doc comment says why it is clearer whole (a line starting "Long by design:").
#[test]
fn no_function_of_the_workspace_is_over_80_lines_without_a_reason() {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(workspace().join("crates")).unwrap() {
        files.extend(rust_files(&entry.unwrap().path().join("src")));
    }
    assert!(files.len() > 50, "found only {} source files", files.len());
    let long = long_functions(&files, 80).unwrap();
    let unexplained: Vec<&LongFunction> = long.iter().filter(|f| f.reason.is_none()).collect();
    assert!(
        unexplained.is_empty(),
        "functions over 80 lines without a `{LONG_BY_DESIGN}` line in their doc comment:\n{}",
        listing(&unexplained)
    );
}

#[test]
fn trainer_functions_read_as_short_steps() {
    let dir = workspace().join("crates/logo-algo/src/trainer");
    let files = rust_files(&dir);
    assert!(
        files.len() >= 3,
        "trainer files not found in {}",
        dir.display()
    );
    let long = long_functions(&files, 60).unwrap();
    assert!(
        long.is_empty(),
        "trainer functions over 60 lines:\n{}",
        listing(&long.iter().collect::<Vec<_>>())
    );
}

#[test]
fn no_tracked_file_cites_a_file_outside_the_repository() {
    // Spelled in halves so that this test does not find itself; the file name alone
    // catches a citation broken over two comment lines.
    let outside = ["LOGO", "-FACTS"].concat();
    let file_name = ["FACTS", ".md"].concat();
    let root = workspace();
    let listed = std::process::Command::new("git")
        .arg("ls-files")
        .current_dir(&root)
        .output();
    let Some(listed) = listed.ok().filter(|o| o.status.success()) else {
        panic!("git ls-files failed in {}", root.display());
    };
    let mut citing = Vec::new();
    for file in String::from_utf8_lossy(&listed.stdout).lines() {
        let Ok(bytes) = std::fs::read(root.join(file)) else {
            continue;
        };
        let text = String::from_utf8_lossy(&bytes);
        if text.contains(&outside) || text.contains(&file_name) {
            citing.push(file.to_string());
        }
    }
    assert!(citing.is_empty(), "files citing {outside}: {citing:?}");
}

// ---- the rules themselves can fail ----

static NEXT: AtomicUsize = AtomicUsize::new(0);

/// A throwaway crate `src/` folder holding the given files.
fn fake_crate(files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "logo-lint-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    for (path, text) in files {
        let path = dir.join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

fn cycles_in(files: &[(&str, &str)]) -> Vec<Vec<String>> {
    let dir = fake_crate(files);
    let graph = ModuleGraph::load("fake", &dir).unwrap();
    let cycles = graph
        .cycles()
        .into_iter()
        .map(|c| {
            let mut names: Vec<String> = c.iter().map(|e| display(&e.from)).collect();
            names.sort();
            names.dedup();
            names
        })
        .collect();
    std::fs::remove_dir_all(dir).ok();
    cycles
}

#[test]
fn a_child_using_its_parent_that_uses_it_is_a_cycle() {
    let cycles = cycles_in(&[
        ("lib.rs", "pub mod update;"),
        (
            "update/mod.rs",
            "mod clip;\npub fn step() { clip::run() }\npub(crate) const LIMIT: f64 = 1.0;",
        ),
        (
            "update/clip.rs",
            "use super::LIMIT;\npub fn run() { let _ = LIMIT; }",
        ),
    ]);
    assert_eq!(
        cycles,
        vec![vec!["update".to_string(), "update::clip".to_string()]]
    );
}

#[test]
fn paths_in_code_count_as_well_as_use_items() {
    let cycles = cycles_in(&[
        ("lib.rs", "mod a;\nmod b;"),
        ("a.rs", "pub fn f() { crate::b::g() }"),
        ("b.rs", "pub fn g() {}\npub fn h() { let _ = crate::a::f; }"),
    ]);
    assert_eq!(cycles, vec![vec!["a".to_string(), "b".to_string()]]);
}

#[test]
fn a_crate_root_re_export_is_followed_to_its_module() {
    let cycles = cycles_in(&[
        (
            "lib.rs",
            "mod config;\nmod trainer;\npub use config::Config;\npub use trainer::Trainer;",
        ),
        ("config.rs", "pub struct Config;"),
        (
            "trainer.rs",
            "use crate::Config;\npub struct Trainer(Config);",
        ),
    ]);
    assert!(cycles.is_empty(), "{cycles:?}");
    // ...but a real circle through a re-export is still one.
    let cycles = cycles_in(&[
        (
            "lib.rs",
            "mod config;\nmod trainer;\npub use config::Config;\npub use trainer::Trainer;",
        ),
        (
            "config.rs",
            "pub struct Config;\nfn f(_: crate::Trainer) {}",
        ),
        (
            "trainer.rs",
            "use crate::Config;\npub struct Trainer(Config);",
        ),
    ]);
    assert_eq!(
        cycles,
        vec![vec!["config".to_string(), "trainer".to_string()]]
    );
}

#[test]
fn unit_test_modules_and_other_crates_are_left_out() {
    let cycles = cycles_in(&[
        ("lib.rs", "mod a;\nmod b;\nuse std::fmt;"),
        (
            "a.rs",
            "pub fn f() { crate::b::g() }\n#[cfg(test)]\nmod tests { use super::*; use crate::a::f; }",
        ),
        (
            "b.rs",
            "pub fn g() {}\n#[cfg(test)]\nmod tests { fn t() { crate::a::f() } }",
        ),
    ]);
    assert!(cycles.is_empty(), "{cycles:?}");
}

#[test]
fn glob_imports_resolve_to_the_module_that_defines_the_name() {
    let cycles = cycles_in(&[
        ("lib.rs", "mod a;\nmod prelude;\nmod b;"),
        ("prelude.rs", "pub use crate::b::*;"),
        ("b.rs", "pub fn g() {}"),
        ("a.rs", "use crate::prelude::g;\npub fn f() { g() }"),
    ]);
    assert!(cycles.is_empty(), "{cycles:?}");
}

#[test]
fn long_functions_are_found_with_their_length() {
    let body: String = (0..70).map(|i| format!("    let _x{i} = {i};\n")).collect();
    let text =
        format!("fn short() {{}}\nstruct S;\nimpl S {{\n    fn long(&self) {{\n{body}    }}\n}}\n");
    let dir = fake_crate(&[("lib.rs", &text)]);
    let found = long_functions(&[dir.join("lib.rs")], 60).unwrap();
    std::fs::remove_dir_all(dir).ok();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        (found[0].name.as_str(), found[0].line, found[0].lines),
        ("long", 4, 72)
    );
    assert_eq!(found[0].reason, None);
    // A reason in the doc comment is found; a plain comment is not one.
    let with_reason = text.replace(
        "    fn long",
        "    /// Sums.\n    /// Long by design: a port kept line for line.\n    fn long",
    );
    let plain = text.replace(
        "    fn long",
        "    // Long by design: not a doc comment.\n    fn long",
    );
    let dir = fake_crate(&[("a.rs", &with_reason), ("b.rs", &plain)]);
    let found = long_functions(&[dir.join("a.rs"), dir.join("b.rs")], 60).unwrap();
    std::fs::remove_dir_all(dir).ok();
    assert_eq!(
        found[0].reason.as_deref(),
        Some("a port kept line for line.")
    );
    assert_eq!(found[1].reason, None);
}
