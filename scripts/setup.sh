#!/usr/bin/env bash
# Sets up everything logo-rl needs on a fresh machine. Idempotent: a second run checks
# hashes, repacks the wheel and returns in a few seconds.
#
#   1. a Python venv (.venv) with the pinned packages of scripts/requirements.txt,
#      fetched from PyPI with pip: the Gymnasium oracle for the parity tests;
#   2. libmujoco.so.3.17.0 from the mujoco==3.17.0 wheel -> third_party/mujoco/lib/
#      (the committed linker script libmujoco.so there points at it);
#   3. the MJCF files from the gymnasium==1.4.0 wheel -> models/;
#   4. the Python package logo_rl (crates/logo-py), built by maturin into a wheel
#      (target/wheels/) and installed into .venv.
# Every extracted file is checked against the committed SHA256SUMS.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

say() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: error: %s\n' "$*" >&2; exit 1; }

command -v python3 >/dev/null || die "python3 is required (3.10 or newer)"

# 1. venv with the pinned packages. A stamp holding the requirements' hash skips pip
#    when nothing changed.
venv="$root/.venv"
stamp="$venv/.logo-requirements.sha256"
want="$(sha256sum scripts/requirements.txt | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  say "creating the Python venv .venv (pip install -r scripts/requirements.txt)"
  python3 -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r scripts/requirements.txt \
    || die "pip could not install scripts/requirements.txt (is PyPI reachable?)"
  echo "$want" > "$stamp"
fi
site="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"

# 2 and 3. Copy from the installed wheels, then verify against the committed hashes.
install_checked() { # <sums file> <dest dir> <source for each name: function>
  local sums="$1" dest="$2" resolve="$3" line hash name src
  while read -r hash name; do
    [ -n "$hash" ] || continue
    if [ -f "$dest/$name" ] && [ "$(sha256sum "$dest/$name" | cut -d' ' -f1)" = "$hash" ]; then
      continue
    fi
    src="$("$resolve" "$name")"
    [ -f "$src" ] || die "$src is missing from the installed wheel"
    mkdir -p "$(dirname "$dest/$name")"
    cp "$src" "$dest/$name.tmp" && mv "$dest/$name.tmp" "$dest/$name"
    [ "$(sha256sum "$dest/$name" | cut -d' ' -f1)" = "$hash" ] \
      || die "$dest/$name: sha256 differs from $sums (the wheel changed?)"
    say "installed $dest/$name"
  done < "$sums"
}
mujoco_file() { echo "$site/mujoco/$(basename "$1")"; }
asset_file() { echo "$site/gymnasium/envs/mujoco/assets/$1"; }
install_checked third_party/mujoco/SHA256SUMS third_party/mujoco mujoco_file
install_checked models/SHA256SUMS models asset_file

# 4. The wheel: cargo rebuilds only what changed, pip reinstalls it (a second; the venv
#    holds its pinned dependencies already, hence --no-deps).
say "building the Python package logo_rl (maturin build --release)"
rm -f target/wheels/logo_rl-*.whl
"$venv/bin/maturin" build --release --quiet -m crates/logo-py/Cargo.toml --out target/wheels \
  || die "maturin could not build crates/logo-py"
wheel="$(ls target/wheels/logo_rl-*.whl)"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps --force-reinstall "$wheel" \
  || die "pip could not install $wheel"
say "installed $(basename "$wheel") into .venv"

say "ready: MuJoCo 3.17.0 in third_party/mujoco/lib, MJCF models in models/, Python oracle and logo_rl in .venv"
