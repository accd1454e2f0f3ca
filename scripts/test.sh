#!/usr/bin/env bash
# The test command: set up (idempotent), check formatting and clippy's lints, check the
# Gymnasium and rliable oracles have not drifted from the committed fixtures, then run
# every Rust test in release mode (MuJoCo and burn are too slow unoptimised, and the
# main job shares this build), then the Python package's tests with pytest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

./scripts/setup.sh
# Binaries find libmujoco by an rpath relative to ./target; this also covers a
# CARGO_TARGET_DIR outside the checkout.
# Tests that use the Python oracle fail instead of skipping when it is missing.
export LOGO_REQUIRE_PYTHON=1
# On CI the Slurm integration test must run (it installs and starts a single-node
# cluster through scripts/slurm-cluster.sh, as root, and stops it at the end).
if [ "${CI:-}" = true ]; then
  export LOGO_REQUIRE_SLURM=1
fi
export LD_LIBRARY_PATH="$root/third_party/mujoco/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

echo "== cargo fmt --check and cargo clippy --all-targets -- -D warnings"
cargo fmt --all --check
cargo clippy --all-targets -- -D warnings

echo "== parity fixtures vs the Gymnasium 1.4.0 oracle"
.venv/bin/python -W ignore tests/parity/generate.py --check tests/parity/fixtures

echo "== the statistics' fixture vs the rliable package (crates/logo-stats/tests/rliable.rs)"
.venv/bin/python tests/stats/rliable_reference.py --check tests/stats/rliable.json

echo "== one compilation at set-up: the wheel, the binary and the workspace share features"
python3 scripts/check_one_build.py

echo "== the tables of docs/findings/ and docs/history.md vs the metrics in docs/results/"
.venv/bin/python scripts/check_results.py
.venv/bin/python tests/python/check_results_fails.py

echo "== what every clone fetches: file sizes, docs/results/ and runs/ (scripts/check_sizes.sh)"
./scripts/check_sizes.sh
python3 scripts/slim_results.py --check
./tests/python/check_sizes_fails.sh

echo "== every relative link and section link in the Markdown resolves"
python3 scripts/check_links.py
python3 tests/python/check_links_fails.py

# Videos (crates/logo-cli/tests/video.rs): ffmpeg encodes, Mesa's EGL renders offscreen.
if ! command -v ffmpeg >/dev/null || ! ls /usr/lib/*/libEGL_mesa.so.0 >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "== installing ffmpeg and Mesa's EGL (libegl1 libegl-mesa0 libgl1-mesa-dri) for the video tests"
    pkgs="ffmpeg libegl1 libegl-mesa0 libgl1-mesa-dri"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q $pkgs >/dev/null \
      || { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $pkgs >/dev/null; }
  fi
fi
[ "${CI:-}" = true ] && export LOGO_REQUIRE_VIDEO=1

echo "== cargo test --release --workspace"
cargo test --release --workspace "$@"

# The wheel for users elsewhere (manylinux, no path of this machine): a build of its own,
# audited and installed into a fresh venv by crates/logo-py/tests/test_wheel.py.
echo "== scripts/wheel.sh (the distribution wheel, dist/)"
./scripts/wheel.sh

# The Python package (built and installed into .venv by setup.sh); its tests compare
# with the `logo` binary the Rust tests just built.
echo "== pytest crates/logo-py/tests (the Python package logo_rl)"
.venv/bin/python -m pytest crates/logo-py/tests

# burn's wgpu backend, on Mesa's lavapipe (Vulkan on the CPU) where there is no GPU: the
# feature is a separate build of logo-cli and the crates it passes the feature to.
if ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "== installing mesa-vulkan-drivers (lavapipe) for the wgpu tests"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q mesa-vulkan-drivers libvulkan1 >/dev/null \
      || { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q mesa-vulkan-drivers libvulkan1 >/dev/null; }
  fi
fi
[ "${CI:-}" = true ] && export LOGO_REQUIRE_WGPU=1
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
echo "== cargo test --release -p logo-cli --features wgpu --test wgpu"
cargo test --release -p logo-cli --features wgpu --test wgpu "$@"
