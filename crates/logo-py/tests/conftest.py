"""Shared paths and helpers of the logo_rl tests (run by ./scripts/test.sh with pytest)."""

import csv
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
IDP_CONFIG = ROOT / "configs" / "logo" / "inverted_double_pendulum.toml"


@pytest.fixture(scope="session")
def logo_bin() -> Path:
    """The `logo` binary the Rust tests built (`cargo test --release` builds it)."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = Path(os.environ.get("LOGO_BIN", target / "release" / "logo"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it with `cargo build --release` (or set LOGO_BIN)")
    return path


def run_logo(logo_bin: Path, *args: str) -> str:
    done = subprocess.run(
        [str(logo_bin), *args], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, f"logo {' '.join(args)} failed:\n{done.stderr}"
    return done.stdout


def metrics_without_timings(run_dir: Path) -> list[dict[str, str]]:
    """metrics.csv's rows without the timing columns (wall_s, t_*)."""
    with open(run_dir / "metrics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows, f"{run_dir}/metrics.csv has no rows"
    return [
        {k: v for k, v in row.items() if k != "wall_s" and not k.startswith("t_")}
        for row in rows
    ]
