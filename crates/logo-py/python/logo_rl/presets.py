"""The repository's training configs inside the package, with the demonstrations they
name: ``logo_rl.presets()`` lists them, ``logo_rl.train("new-task", ...)`` runs one."""

from __future__ import annotations

import os
from pathlib import Path

from ._errors import LogoValueError
from . import _logo_rl


def presets() -> dict[str, str]:
    """Every preset's name and what it is: ``"new-task"`` (LOGO on a task of your own:
    give ``env=`` and ``demos=``), and each config of the repository's ``configs/`` as
    ``"<algorithm>/<task>"`` (``"logo/hopper"``, ``"trpo/inverted_double_pendulum"``,
    ``"logo-fast/walker2d"``), the LOGO paper's demonstrations included."""
    return {name: about for name, _, about in _logo_rl.presets()}


def cache_root() -> Path:
    """Where presets are written out to be read: ``$LOGO_RL_PRESETS``, else
    ``~/.cache/logo_rl/presets-<version>``."""
    given = os.environ.get("LOGO_RL_PRESETS")
    if given:
        return Path(given)
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "logo_rl" / f"presets-{_logo_rl.__version__}"


def preset_path(name: str) -> Path:
    """The preset's config file, written out with the files it names in the repository's
    layout (so its relative paths hold) under :func:`cache_root`."""
    paths = {n: path for n, path, _ in _logo_rl.presets()}
    if name not in paths:
        known = ", ".join(sorted(paths))
        raise LogoValueError(f"{name!r} is not a preset; logo_rl.presets() lists them: {known}")
    root = cache_root()
    for inside, data in _logo_rl.preset_data():
        _write_once(root / inside, data)
    config = root / paths[name]
    _write_once(config, _logo_rl.preset_text(name).encode())
    return config


def _write_once(path: Path, data: bytes) -> None:
    """Writes `path` unless it already holds `data` (whole, via a temporary file, so that
    two processes never read half a file)."""
    try:
        if path.stat().st_size == len(data) and path.read_bytes() == data:
            return
    except OSError:
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(f".{path.name}.{os.getpid()}.partial")
    partial.write_bytes(data)
    os.replace(partial, path)
