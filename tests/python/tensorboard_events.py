"""TensorBoard's own reader as the oracle for logo-rl's event files
(crates/logo-cli/tests/tensorboard.rs).

  tensorboard_events.py RUN_DIR

loads RUN_DIR with tensorboard's EventAccumulator (what `tensorboard --logdir` runs on
each run folder) and prints JSON: {"scalars": {tag: [[step, value], ...]}, "text":
{tag: [string, ...]}}.
"""
import json
import sys

from tensorboard.backend.event_processing.event_accumulator import EventAccumulator


def main():
    accumulator = EventAccumulator(sys.argv[1], size_guidance={"scalars": 0, "tensors": 0})
    accumulator.Reload()
    tags = accumulator.Tags()
    scalars = {
        tag: [[event.step, event.value] for event in accumulator.Scalars(tag)]
        for tag in tags["scalars"]
    }
    text = {}
    for tag in tags["tensors"]:
        text[tag] = [
            b"".join(event.tensor_proto.string_val).decode()
            for event in accumulator.Tensors(tag)
        ]
    json.dump({"scalars": scalars, "text": text}, sys.stdout)


if __name__ == "__main__":
    main()
