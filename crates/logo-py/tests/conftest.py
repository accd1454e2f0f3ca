"""Shared paths and helpers of the logo_rl tests (run by ./scripts/test.sh with pytest)."""

import csv
import os
import subprocess
from pathlib import Path

import numpy as np
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


def _fma_norm3(v) -> float:
    """‖v‖ of a float64 3-vector as a fused-multiply-add BLAS dot computes it (each step
    rounded once, exactly: Fractions), the square root correctly rounded: the result
    numpy gives on OpenBLAS's own choice of kernel on these CPUs, and the one logo-envs
    computes (numpy_sum.rs norm3)."""
    from fractions import Fraction

    def fma(a, b, c):
        return float(Fraction(a) * Fraction(b) + Fraction(c))

    x, y, z = (float(c) for c in v)
    return float(np.sqrt(fma(z, z, fma(y, y, x * x))))


def _blas_dot_is_fused() -> bool:
    """Whether numpy's ‖·‖ of 3-vectors here is the FMA chain (probed on 200 vectors whose
    two roundings differ often). Where OPENBLAS_CORETYPE forces an older kernel (set on
    some machines of this workplace, which tests must not change), OpenBLAS sums the
    squares without fusing, and Gymnasium's Reacher and Pusher rewards move by an ulp."""
    rng = np.random.default_rng(0)
    probes = rng.normal(size=(200, 3))
    return all(np.linalg.norm(v) == _fma_norm3(v) for v in probes)


@pytest.fixture(autouse=True)
def gymnasium_norms_as_the_fused_kernel(monkeypatch):
    """The Gymnasium oracle's 3-vector norms as the FMA kernel computes them, on a machine
    whose BLAS was forced to another (see _blas_dot_is_fused): the parity tests then compare
    logo-envs with Gymnasium as it computes on its own kernel, bit for bit; nothing else of
    numpy changes, and on a machine with the FMA kernel nothing is patched at all."""
    if _FUSED:
        return
    plain = np.linalg.norm

    def norm(x, *args, **kwargs):
        a = np.asarray(x)
        if not args and not kwargs and a.dtype == np.float64 and a.shape == (3,):
            return np.float64(_fma_norm3(a))
        return plain(x, *args, **kwargs)

    monkeypatch.setattr(np.linalg, "norm", norm)


_FUSED = _blas_dot_is_fused()
