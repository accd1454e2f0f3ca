"""logo_rl: LOGO (learning online with guidance offline) from Python.

logo-rl's Rust trainer, its Gymnasium-exact MuJoCo envs and its trained policies:

- ``import logo_rl`` registers every env of ``logo envs`` with Gymnasium as
  ``logo_rl/<id>`` (``gymnasium.make("logo_rl/SparseHopper-v4")``);
- :func:`train` runs ``logo train`` in this process and returns a :class:`Run`;
- :func:`compare` sets LOGO beside the baselines on a task (``logo compare``);
- :func:`bc` fits a policy to demonstrations (behaviour cloning, ``logo bc``);
- :func:`load` opens a checkpoint's policy (:class:`Policy`);
- :class:`LogoVectorEnv`: N copies of an env on Rust threads, Gymnasium's VectorEnv API;
- :class:`SparseReward`: logo-rl's sparse kinds on any Gymnasium env;
- :func:`record`: demonstrations of a policy or a controller into Minari.

The extension uses MuJoCo 3.17.0 from the ``mujoco`` wheel (loaded here, before it), and
the envs read their MJCF files from the ``gymnasium`` 1.4.0 wheel (``LOGO_MODELS_DIR``
overrides that).
"""

import importlib.util as _util
import os as _os


def _models_dir() -> str:
    spec = _util.find_spec("gymnasium")
    if spec is None or spec.origin is None:
        raise ImportError("logo_rl needs gymnasium==1.4.0 (pip install gymnasium==1.4.0)")
    return _os.path.join(_os.path.dirname(spec.origin), "envs", "mujoco", "assets")


# Read by the Rust side each time it loads a model; a user's own setting wins.
_os.environ.setdefault("LOGO_MODELS_DIR", _models_dir())

# The MuJoCo the extension was built against; pyproject.toml pins the wheel to match.
_MUJOCO_LIBRARY = "libmujoco.so.3.17.0"


def _load_mujoco() -> None:
    """Loads the mujoco wheel's libmujoco with its symbols global, before the extension.

    The distribution wheel's extension does not name libmujoco in its link table (a library
    from outside the wheel there would cost it its manylinux tag: scripts/unlink_mujoco.py),
    so its MuJoCo symbols are resolved against this one when it is imported. A checkout's
    build names it as well; the loader then finds this copy already loaded, by its soname.
    """
    import ctypes

    spec = _util.find_spec("mujoco")
    folders = list(spec.submodule_search_locations or []) if spec else []
    for folder in folders:
        path = _os.path.join(folder, _MUJOCO_LIBRARY)
        if _os.path.isfile(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
            return
    where = f" (the installed mujoco, in {folders[0]}, has no {_MUJOCO_LIBRARY})" if folders else ""
    raise ImportError(f"logo_rl needs mujoco==3.17.0 (pip install mujoco==3.17.0){where}")


_load_mujoco()

from ._logo_rl import MUJOCO_VERSION, LogoError, __version__, env_ids  # noqa: E402
from ._errors import LogoFileNotFoundError, LogoTypeError, LogoValueError  # noqa: E402
from .bc import Cloned, bc  # noqa: E402
from .compare import compare  # noqa: E402
from .envs import LogoEnv, register_envs  # noqa: E402
from .policy import Policy, load  # noqa: E402
from .presets import presets  # noqa: E402
from .record import Dataset, Recording, read_dataset, record  # noqa: E402
from .run import Run, train  # noqa: E402
from .vector import LogoVectorEnv  # noqa: E402
from .wrappers import SparseReward, Success  # noqa: E402

register_envs()

__all__ = [
    "Cloned",
    "Dataset",
    "LogoEnv",
    "LogoError",
    "LogoFileNotFoundError",
    "LogoTypeError",
    "LogoValueError",
    "LogoVectorEnv",
    "MUJOCO_VERSION",
    "Policy",
    "Recording",
    "Run",
    "SparseReward",
    "Success",
    "__version__",
    "bc",
    "compare",
    "env_ids",
    "load",
    "presets",
    "read_dataset",
    "record",
    "register_envs",
    "train",
]
