//! The Python exception of the Rust side's errors.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _logo_rl,
    LogoError,
    PyException,
    "An error of logo-rl's Rust side (a config, a checkpoint, an env), on one line."
);

/// anyhow's chain on one line, as `logo` prints it.
pub(crate) fn logo_error(e: &anyhow::Error) -> PyErr {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    LogoError::new_err(in_python_words(&line))
}

/// An error of the Rust envs (an unknown id, a non-finite action) as a LogoError.
pub(crate) fn env_error(e: impl std::fmt::Display) -> PyErr {
    LogoError::new_err(e.to_string())
}

/// `logo train`'s flags and the keyword arguments of `logo_rl.train` that say the same.
const FLAG_WORDS: [(&str, &str); 8] = [
    ("--resume", "resume="),
    ("--out", "out="),
    ("--iterations", "iterations="),
    ("--config", "config="),
    ("--seed", "seed="),
    ("--engine", "engine="),
    ("--backend", "backend="),
    ("--dtype", "dtype="),
];

/// A line of the trainer's (an error, a progress line) in Python's words: each of
/// `logo train`'s flags named as the keyword argument that does the same.
pub(crate) fn in_python_words(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    'scan: while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let tail = &rest[at..];
        for (flag, word) in FLAG_WORDS {
            let after = &tail[flag.len().min(tail.len())..];
            let whole = !after.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '-');
            if tail.starts_with(flag) && whole {
                out.push_str(word);
                // "--resume runs/a" reads "resume=runs/a"; a flag named in a sentence
                // ("--iterations extends it") keeps its space.
                let value = after.strip_prefix(' ').filter(|v| {
                    v.starts_with(|c: char| c.is_ascii_digit() || "/.~".contains(c))
                        || v.split(' ').next().is_some_and(|w| w.contains('/'))
                });
                rest = value.unwrap_or(after);
                continue 'scan;
            }
        }
        out.push_str("--");
        rest = &tail[2..];
    }
    out.push_str(rest);
    out
}
