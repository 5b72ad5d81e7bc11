"""The environment for a test's `python -m libkin` subprocess: this
checkout's package first on PYTHONPATH, and no fault injection inherited
from the test's own environment (LIBKIN_STORE_KILL_AFTER)."""
import os
import pathlib

import libkin


def libkin_env(**extra):
    env = dict(os.environ)
    src = str(pathlib.Path(libkin.__file__).resolve().parents[1])
    env["PYTHONPATH"] = src + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("LIBKIN_STORE_KILL_AFTER", None)
    env.update(extra)
    return env
