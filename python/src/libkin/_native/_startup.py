"""What the `libkin` command does when the C library cannot be loaded.

The package's __init__ loads the library, and both `libkin` (the console
script) and `python -m libkin` import the package before any command-line
code runs; so the one-line error of the command line is given here, from
the package's import, when the process is that command.
"""
from __future__ import annotations

import os
import sys


def invoked_as_command() -> bool:
    """Whether this process is the `libkin` command (console script or ``python -m libkin``)."""
    if sys.argv and os.path.basename(sys.argv[0]) == "libkin":
        return True
    orig = list(getattr(sys, "orig_argv", []))
    return any(a == "-m" and b == "libkin" for a, b in zip(orig, orig[1:])) or "-mlibkin" in orig


def exit_if_command(exc: ImportError) -> None:
    """Print `exc` as one line and exit with status 1 if this is the command line; else return."""
    if invoked_as_command():
        print("libkin: " + " ".join(str(exc).split()), file=sys.stderr)
        raise SystemExit(1)
