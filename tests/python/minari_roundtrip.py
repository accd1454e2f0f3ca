"""Both directions of the Minari round trip, driven by crates/logo-data/tests/minari.rs.

  write DIR   : create a dataset with minari 0.5.4 under DIR (DIR/data/...) and dump its
                values to DIR/expected.json
  read DIR    : load DIR/data with minari and compare it with DIR/expected.json (written
                by the Rust side); exits non-zero on any difference
  d4rl FILE [narrow|short]
              : write a small D4RL-style flat HDF5 file with h5py, as D4RL's own files
                are (float32 arrays, bool terminals/timeouts, next_observations);
                narrow/short: next_observations one column or two rows short
"""
import json
import os
import sys

import numpy as np


def episodes_json(episodes):
    return [
        {
            "observations": np.asarray(e["observations"], dtype=np.float64).tolist(),
            "actions": np.asarray(e["actions"], dtype=np.float64).tolist(),
            "rewards": np.asarray(e["rewards"], dtype=np.float64).tolist(),
            "terminations": [bool(x) for x in e["terminations"]],
            "truncations": [bool(x) for x in e["truncations"]],
        }
        for e in episodes
    ]


def write(root):
    os.environ["MINARI_DATASETS_PATH"] = root
    import gymnasium as gym
    import minari
    from minari.data_collector import EpisodeBuffer

    rng = np.random.default_rng(7)
    obs_dim, act_dim = 3, 2
    buffers, expected = [], []
    for i, steps in enumerate([5, 1, 9]):
        ep = {
            "observations": rng.normal(size=(steps + 1, obs_dim)),
            "actions": rng.uniform(-1, 1, size=(steps, act_dim)),
            "rewards": rng.normal(size=steps),
            "terminations": np.array([False] * (steps - 1) + [i != 1]),
            "truncations": np.array([False] * (steps - 1) + [i == 1]),
        }
        expected.append(ep)
        buffers.append(
            EpisodeBuffer(
                id=i,
                observations=ep["observations"],
                actions=ep["actions"],
                rewards=ep["rewards"],
                terminations=ep["terminations"],
                truncations=ep["truncations"],
            )
        )
    minari.create_dataset_from_buffers(
        "test/roundtrip-v0",
        buffers,
        observation_space=gym.spaces.Box(-np.inf, np.inf, (obs_dim,), np.float64),
        action_space=gym.spaces.Box(-1.0, 1.0, (act_dim,), np.float64),
        algorithm_name="random",
    )
    path = os.path.join(root, "test", "roundtrip-v0")
    with open(os.path.join(path, "expected.json"), "w") as f:
        json.dump(episodes_json(expected), f)
    print(path)


def read(root):
    from minari import MinariDataset

    dataset = MinariDataset(os.path.join(root, "data"))
    with open(os.path.join(root, "expected.json")) as f:
        expected = json.load(f)
    got = episodes_json(
        {
            "observations": e.observations,
            "actions": e.actions,
            "rewards": e.rewards,
            "terminations": e.terminations,
            "truncations": e.truncations,
        }
        for e in dataset.iterate_episodes()
    )
    assert dataset.total_episodes == len(expected), (dataset.total_episodes, len(expected))
    assert dataset.total_steps == sum(len(e["rewards"]) for e in expected)
    for i, (g, e) in enumerate(zip(got, expected)):
        for key in e:
            assert g[key] == e[key], f"episode {i}, {key}: {g[key]} != {e[key]}"
    for e in dataset.iterate_episodes():
        assert e.terminations.dtype == np.bool_, e.terminations.dtype
    print(f"minari read {len(got)} episodes written by logo-rl: identical")


def d4rl(path, broken=None):
    import h5py

    rng = np.random.default_rng(3)
    steps, obs_dim, act_dim = 12, 3, 2
    obs = rng.normal(size=(steps, obs_dim)).astype(np.float32)
    terminals = np.zeros(steps, dtype=bool)
    timeouts = np.zeros(steps, dtype=bool)
    terminals[3] = True  # episode 0: rows 0-3, terminated
    timeouts[8] = True  # episode 1: rows 4-8, timed out; episode 2: rows 9-11, cut
    with h5py.File(path, "w") as f:
        f.create_dataset("observations", data=obs, compression="gzip")
        following = obs + 1.0
        if broken == "narrow":
            following = following[:, :-1]
        elif broken == "short":
            following = following[:-2]
        f.create_dataset("next_observations", data=following)
        f.create_dataset("actions", data=rng.uniform(-1, 1, (steps, act_dim)).astype(np.float32))
        f.create_dataset("rewards", data=np.arange(steps, dtype=np.float32))
        f.create_dataset("terminals", data=terminals)
        f.create_dataset("timeouts", data=timeouts)


if __name__ == "__main__":
    {"write": write, "read": read, "d4rl": d4rl}[sys.argv[1]](*sys.argv[2:])
