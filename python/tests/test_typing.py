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


def test_public_api_has_numpydoc_sections():
    """Every public method and function of the API documents its parameters
    (Parameters) and what it returns (Returns/Yields), and is annotated."""
    import inspect

    import libkin

    targets = [(f"Assembly.{n}", f) for n, f in vars(libkin.Assembly).items()]
    for base in libkin.Assembly.__mro__[1:-1]:
        targets += [(f"{base.__name__}.{n}", f) for n, f in vars(base).items()]
    targets += [(n, getattr(libkin, n)) for n in ("solve_quadrics", "load_json", "load_model", "to_json")]
    targets += [(f"errors.{n}", getattr(libkin.errors, n)) for n in ("check", "error_class")]
    checked = 0
    for name, f in targets:
        f = getattr(f, "__func__", f)
        if name.split(".")[-1].startswith("_") or not inspect.isfunction(f):
            continue
        doc = inspect.getdoc(f) or ""
        sig = inspect.signature(f)
        params = [p for p in sig.parameters if p not in ("self", "cls")]
        assert all(sig.parameters[p].annotation is not inspect.Parameter.empty for p in params), name
        assert sig.return_annotation is not inspect.Signature.empty, name
        if params:
            assert "Parameters\n----------" in doc, name
            for p in params:
                assert p in doc, (name, p)
        if sig.return_annotation not in (None, "None"):
            assert "Returns\n-------" in doc or "Yields\n------" in doc, name
        checked += 1
    assert checked >= 25
