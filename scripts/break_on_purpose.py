#!/usr/bin/env python3
"""Each baseline's tests must fail when its algorithm is broken. This breaks each one on
purpose, one edit at a time, runs the tests that guard it, and puts the code back: every
line should end "fails, as it must". Exit status 1 if a broken algorithm still passes
its tests, 2 if an edit no longer applies or builds (update the list below). About two
minutes per edit: each rebuilds the crates above the change.

Usage: scripts/break_on_purpose.py
"""
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (what breaks, file, the line as it is, the line broken, the tests that must fail)
BREAKS = [
    ("BC: the mean's gradient sign flipped", "crates/logo-algo/src/bc.rs",
     "let mut grad = engine.vjp(&current.mean, &trace, d_means);",
     "let mut grad: Vec<f64> = engine.vjp(&current.mean, &trace, d_means)"
     ".into_iter().map(|g| -g).collect();",
     ["-p", "logo-algo", "--test", "bc"]),
    ("BC: log σ's gradient sign flipped", "crates/logo-algo/src/bc.rs",
     "grad.extend(engine.download(d_log_std));",
     "grad.extend(engine.download(d_log_std).into_iter().map(|g| -g));",
     ["-p", "logo-algo", "--test", "bc"]),
    ("BC-TRPO: the clone fitted, then dropped", "crates/logo-algo/src/trainer/mod.rs",
     "networks.policy = fitted.to_module(engine, networks.policy.clone());",
     "let _ = fitted.to_module(engine, networks.policy.clone());",
     ["-p", "logo-cli", "--test", "bc"]),
    ("GAIL: the env reward's weight ignored", "crates/logo-algo/src/config.rs",
     ".map(|(r, c)| self.env * r + self.discriminator * c)",
     ".map(|(r, c)| r + self.discriminator * c)",
     ["-p", "logo-algo", "--test", "baselines"]),
    ("POfD: the discriminator's weight ignored", "crates/logo-algo/src/config.rs",
     ".map(|(r, c)| self.env * r + self.discriminator * c)",
     ".map(|(r, c)| self.env * r + c)",
     ["-p", "logo-algo", "--test", "baselines"]),
    ("DAPG: F·v over the demonstration rows too", "crates/logo-algo/src/policy_update/trpo.rs",
     "let own = batch.rows - batch.demonstration_rows;",
     "let own = batch.rows;",
     ["-p", "logo-algo", "--test", "policy_updates", "--test", "baselines"]),
    ("DAPG: the demonstrations' weight negated", "crates/logo-algo/src/dapg.rs",
     "all.resize(rows, weight);",
     "all.resize(rows, -weight);",
     ["-p", "logo-algo", "--test", "policy_updates", "--test", "baselines"]),
]


def main():
    survivors = 0
    for what, file, before, after, tests in BREAKS:
        path = ROOT / file
        text = path.read_text()
        if text.count(before) != 1:
            print(f"{what}: the line to break is not in {file} once; update this script")
            return 2
        try:
            path.write_text(text.replace(before, after))
            run = subprocess.run(["cargo", "test", "--release", "--no-fail-fast", *tests],
                                 cwd=ROOT, capture_output=True, text=True)
        finally:
            path.write_text(text)
        log = run.stdout + run.stderr
        command = "cargo test --release " + " ".join(tests)
        if "could not compile" in log:
            print(f"{what}: does not build; update this script\n{log[-3000:]}")
            return 2
        failing = [line for line in log.splitlines()
                   if line.startswith("test ") and line.endswith("FAILED")]
        if run.returncode == 0:
            survivors += 1
            print(f"{what}: STILL PASSES ({command})")
        else:
            names = ", ".join(line.split()[1] for line in failing)
            print(f"{what}: fails, as it must ({command}: {names})", flush=True)
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main())
