#!/usr/bin/env python3
"""Makes the runs kept under docs/results/ (or the folders named) hold what
docs/results/README.md says a kept run holds: every safetensors file that carries a
learner's state (critics, discriminator, optimisers, the sampler's position) becomes its
policy alone through `logo export --in-place`, and TensorBoard event files go (the
metrics.csv beside them holds every column). `--check` changes nothing and exits 1 naming
each file that is not so.

    python3 scripts/slim_results.py [--check] [--logo target/release/logo] [PATH ...]
"""
import argparse
import json
import struct
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
POLICY_PREFIXES = ("policy.", "observation_norm.")


def has_learner_state(path: Path) -> bool:
    """Whether the safetensors file PATH holds more than a policy: a resume state, or
    tensors of any network but the policy and the observation statistics."""
    with open(path, "rb") as f:
        (length,) = struct.unpack("<Q", f.read(8))
        header = json.loads(f.read(length))
    meta = json.loads(header.get("__metadata__", {}).get("logo_rl", "{}"))
    extra = meta.get("extra") or {}
    if extra.get("resume") is not None:
        return True
    names = [n for n in header if n != "__metadata__"]
    return any(not n.startswith(POLICY_PREFIXES) for n in names)


def tracked(paths: list[Path]) -> list[Path]:
    """The tracked files under PATHS, and those of PATHS that are files themselves."""
    files = {p.resolve() for p in paths if p.is_file()}
    folders = [str(p) for p in paths if not p.is_file()]
    if folders:
        out = subprocess.run(["git", "ls-files", "-z", "--", *folders], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout
        files |= {ROOT / f for f in out.split("\0") if f}
    return sorted(files)


def shown(path: Path) -> str:
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*", type=Path, default=[Path("docs/results")],
                        help="folders (their tracked files) or files")
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--logo", default=str(ROOT / "target/release/logo"))
    args = parser.parse_args(argv)
    files = tracked(args.paths)
    heavy = [f for f in files if f.suffix == ".safetensors" and f.is_file()
             and has_learner_state(f)]
    events = [f for f in files if f.name.startswith("events.out.tfevents.")]
    if args.check:
        for f in heavy:
            print(f"{shown(f)}: holds a learner state (logo export --in-place)")
        for f in events:
            print(f"{shown(f)}: a TensorBoard event file (metrics.csv holds it)")
        print(f"slim_results: {len(files)} tracked files, {len(heavy)} learner states, "
              f"{len(events)} event files")
        return 1 if heavy or events else 0
    for f in heavy:
        subprocess.run([args.logo, "export", "--checkpoint", str(f), "--in-place"], check=True)
    for f in events:
        subprocess.run(["git", "rm", "-q", str(f)], cwd=ROOT, check=True)
    print(f"slim_results: {len(heavy)} files made policies, {len(events)} event files removed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
