"""The evaluation JSON that scripts/evaluate_exploration.py writes at the end of an exploration, as
the exploration rostests read it."""
import json
import os
import time


def read_result(path):
    """The evaluation at `path`, or None while it is not (completely) written."""
    if not os.path.exists(path):
        return None
    time.sleep(0.5)  # written once, at the end: let the writer finish
    with open(path) as f:
        try:
            return json.load(f)
        except ValueError:
            return None
