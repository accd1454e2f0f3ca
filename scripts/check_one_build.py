#!/usr/bin/env python3
"""Set-up compiles the workspace once: the wheel's build (logo-py alone, by maturin), the
`logo` binary's alone (`cargo build -p logo-cli`) and a workspace-wide build (`cargo run
--bin logo`, `cargo build --release`) must give every crate they share the same features,
or cargo compiles that crate, and all that depends on it, once per feature set.
`cargo tree` says which; exit status 1, naming each crate that differs. Run by test.sh.
"""

import collections
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def features(selection):
    """Each crate built for the target (proc macros left out) and its features."""
    out = subprocess.run(
        ["cargo", "tree", "-e", "normal,no-proc-macro", "--prefix", "none", "-f", "{p}|{f}", *selection],
        capture_output=True, text=True, cwd=ROOT, check=True,
    ).stdout
    found = collections.defaultdict(set)
    for line in out.splitlines():
        if "|" not in line:
            continue
        crate, names = line.replace(" (*)", "").split("|", 1)
        found[re.sub(r" \(.*\)", "", crate).strip()] |= {n for n in names.split(",") if n}
    return found


def main():
    builds = {
        "the wheel (logo-py)": features(["-p", "logo-py"]),
        "the binary (logo-cli)": features(["-p", "logo-cli"]),
        "the workspace": features(["--workspace"]),
    }
    (first, reference), *others = builds.items()
    differ = []
    for name, found in others:
        for crate in sorted(set(found) & set(reference)):
            if found[crate] != reference[crate]:
                extra = sorted(found[crate] - reference[crate])
                missing = sorted(reference[crate] - found[crate])
                differ.append(f"{crate}: {name} adds {extra}, lacks {missing} against {first}")
    for line in differ:
        print(line)
    if differ:
        print("give crates/logo-cli/Cargo.toml's feature-unification block these features")
        return 1
    print(f"one feature set for every shared crate of {', '.join(builds)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
