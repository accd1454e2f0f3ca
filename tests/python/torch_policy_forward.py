#!/usr/bin/env python3
"""Independent oracle for the BC-policy import: reads a PyTorch state-dict file WITHOUT
torch (zipfile + a restricted unpickler + numpy) and prints the policy's mean action and
log-std for the observation rows given as JSON on stdin.

  torch_policy_forward.py POLICY.pt < rows.json  ->  {"mean": [[...], ...], "log_std": [...]}
"""
import collections
import json
import pickle
import sys
import zipfile

import numpy as np

DTYPES = {"DoubleStorage": "<f8", "FloatStorage": "<f4"}


def load_state_dict(path):
    archive = zipfile.ZipFile(path)
    pkl = next(n for n in archive.namelist() if n.endswith("data.pkl"))
    prefix = pkl[: -len("data.pkl")]

    def rebuild(storage, offset, size, stride, *_):
        item = storage.itemsize
        return np.lib.stride_tricks.as_strided(
            storage[offset:], shape=tuple(size), strides=[s * item for s in stride]).copy()

    class Unpickler(pickle.Unpickler):
        def find_class(self, module, name):
            if (module, name) == ("torch._utils", "_rebuild_tensor_v2"):
                return rebuild
            if (module, name) == ("collections", "OrderedDict"):
                return collections.OrderedDict
            if module == "torch" and name in DTYPES:
                return name
            raise pickle.UnpicklingError(f"unexpected global {module}.{name}")

        def persistent_load(self, pid):
            _, storage_type, key, _location, _numel = pid
            return np.frombuffer(archive.read(f"{prefix}data/{key}"), dtype=DTYPES[storage_type])

    return Unpickler(archive.open(pkl)).load()


def main():
    sd = load_state_dict(sys.argv[1])
    x = np.asarray(json.load(sys.stdin), dtype=np.float64)
    i = 0
    while f"affine_layers.{i}.weight" in sd:
        x = np.tanh(x @ sd[f"affine_layers.{i}.weight"].T + sd[f"affine_layers.{i}.bias"])
        i += 1
    mean = x @ sd["action_mean.weight"].T + sd["action_mean.bias"]
    print(json.dumps({"mean": mean.tolist(), "log_std": sd["action_log_std"].ravel().tolist()}))


if __name__ == "__main__":
    main()
