"""The package type-checks: `mypy` with the settings of python/pyproject.toml
(strict on the API modules). Uses a cache in build/ so reruns take ~1 s."""
import pathlib
import subprocess
import sys

import pytest

PYTHON_DIR = pathlib.Path(__file__).resolve().parents[1]
CACHE = PYTHON_DIR.parent / "build" / "mypy_cache"


def test_mypy_is_clean():
    pytest.importorskip("mypy", reason="mypy is in python/requirements-dev.txt")
    r = subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(CACHE), "--no-error-summary"],
                       cwd=PYTHON_DIR, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr


def test_py_typed_marker_ships_with_the_package():
    import libkin

    assert (pathlib.Path(libkin.__file__).parent / "py.typed").is_file()
