"""The exception classes of libkin.errors against the C header's status list,
and the built-in exceptions they derive from."""
import inspect

import numpy as np
import pytest

import libkin
from libkin import errors
from libkin._native import _cdef, _lib


def declared_status_classes():
    return [cls for _, cls in inspect.getmembers(errors, inspect.isclass)
            if issubclass(cls, errors.KinError) and cls is not errors.KinError and cls.__module__ == errors.__name__
            and "code" in vars(cls)]


def test_one_declared_class_per_status_code_of_the_header():
    """Every code of kin_status.h (as generated into the cdef) but KIN_OK has
    exactly one class, with the header's value and name, and no class has a
    code the header lacks: adding a status in C without a class fails here."""
    header = {name: value for value, name in enumerate(_cdef.STATUS_NAMES)}
    assert all(getattr(libkin.lib, name) == value for name, value in header.items())
    classes = declared_status_classes()
    by_name = {cls.name: cls for cls in classes}
    assert len(by_name) == len(classes), "two classes claim the same status"
    assert set(by_name) == set(header) - {"KIN_OK"}
    for name, cls in by_name.items():
        assert cls.code == header[name], name
        assert errors.error_class(cls.code) is cls
        assert cls.__name__ in errors.__all__
        assert cls.__doc__ and name in cls.__doc__
    assert set(errors.BY_CODE) == set(header.values()) - {0}


BASES = {
    "KIN_EINVAL": ValueError, "KIN_EDIM": ValueError, "KIN_EJOINT": IndexError, "KIN_EGEOM": ValueError,
    "KIN_ENOMEM": MemoryError, "KIN_ENOTCONVERGED": ArithmeticError, "KIN_ELAPACK_CONV": ArithmeticError,
    "KIN_EBIFURCATION": RuntimeError, "KIN_ESTATE": RuntimeError, "KIN_ERANGE": IndexError,
    "KIN_ELIMIT": ValueError, "KIN_EIO": OSError, "KIN_EFORMAT": ValueError, "KIN_EMULTIDOF": RuntimeError,
}


@pytest.mark.parametrize("name, base", sorted(BASES.items()))
def test_classes_derive_from_the_builtin_they_mean(name, base):
    cls = errors.error_class(getattr(libkin.lib, name))
    assert issubclass(cls, base) and issubclass(cls, libkin.KinError)
    e = cls("detail", cls.code)
    assert str(e) == "detail" and e.code == cls.code and e.name == name


def test_check_raises_the_class_with_the_c_message():
    with pytest.raises(errors.NotConvergedError, match="relax: iteration did not converge"):
        errors.check(libkin.lib.KIN_ENOTCONVERGED, what="relax")
    errors.check(0)
    with pytest.raises(libkin.KinError) as ei:
        errors.check(999)
    assert type(ei.value) is libkin.KinError and ei.value.code == 999


def test_python_side_argument_errors_are_value_and_type_errors():
    a = libkin.Assembly.threebar("RC")
    with pytest.raises(errors.InvalidArgumentError):
        a.locate(method="bogus")
    with pytest.raises(ValueError):
        a.second_order(weighting="bogus")
    with pytest.raises(errors.InvalidArgumentError, match="state"):
        libkin.Assembly.threebar("RX")
    with pytest.raises(ValueError, match="support"):
        libkin.Assembly.sail(6, 2, support="nowhere")
    with pytest.raises(ValueError, match="solver"):
        libkin.solve_quadrics(np.zeros((1, 2, 2)), solver="bogus")
    with pytest.raises(errors.InvalidArgumentError, match="Q: expected shape"):
        libkin.solve_quadrics(np.zeros((2, 2)))
    with pytest.raises(TypeError):
        a.options = {"rank_tol": 1e-9}
    with pytest.raises(TypeError):
        a.set_direction(["x", "y", "z", "w"])
    for exc in (errors.InvalidArgumentError, errors.ArgumentTypeError):
        assert not issubclass(exc, errors.ModelFormatError)


def test_model_format_error_is_the_format_status():
    with pytest.raises(errors.ModelFormatError) as ei:
        libkin.Assembly.from_json({"dimension": 4})
    assert ei.value.code == libkin.lib.KIN_EFORMAT and isinstance(ei.value, ValueError)


def test_version_is_the_c_library_s_and_pyproject_s():
    import pathlib
    import re

    assert libkin.__version__ == _lib.c_string(libkin.lib.kin_version_string())
    assert libkin.__version__ == ".".join(map(str, _cdef.VERSION))
    pyproject = pathlib.Path(__file__).resolve().parents[1] / "pyproject.toml"
    m = re.search(r'^version\s*=\s*"([^"]+)"', pyproject.read_text(), re.M)
    assert m and m.group(1) == libkin.__version__


def run_cli(*args, **kw):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "libkin", *args], capture_output=True, text=True, timeout=120,
                          **kw)


def test_cli_version_and_exit_statuses(tmp_path):
    r = run_cli("--version")
    assert r.returncode == 0 and r.stdout.strip() == f"libkin {libkin.__version__}"
    # a libkin or file error: status 1, one line on stderr, no traceback
    bad = tmp_path / "bad.json"
    bad.write_text('{"dimension": 2,\n')
    for args in (("analyse", str(tmp_path / "missing.json")), ("analyse", str(bad)), ("analyse", "threebar:RX")):
        r = run_cli(*args)
        assert r.returncode == 1, (args, r.stderr)
        assert r.stderr.startswith("libkin: ") and r.stderr.count("\n") == 1, r.stderr
        assert "Traceback" not in r.stderr
    # usage errors: status 2
    assert run_cli("analyse").returncode == 2
    assert run_cli("no-such-command").returncode == 2
    assert run_cli("locate", "threebar:RC", "--method", "bogus").returncode == 2


def test_cli_interrupt_exits_130():
    import signal
    import subprocess
    import sys
    import time

    # the child with SIGINT's default action, whatever this test runs under: a
    # background job of a non-interactive shell inherits SIGINT ignored, and
    # Python then installs no Ctrl-C handler (so the signal would do nothing)
    p = subprocess.Popen([sys.executable, "-m", "libkin", "follow", "sail:6:2", "--perturb", "0.3",
                          "--steps", "1000000", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(1.5)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert err.strip().splitlines()[-1] == "libkin: interrupted" and "Traceback" not in err


def test_cli_without_a_library_says_so_in_one_line(tmp_path):
    """A copy of the package away from the build tree, with LIBKIN_LIBRARY
    pointing nowhere: the command exits 1 with one line; import raises."""
    import ctypes.util
    import os
    import shutil
    import subprocess
    import sys

    if ctypes.util.find_library("kin"):
        pytest.skip("a system-wide libkin would be found")
    shutil.copytree(pathlib_package(), tmp_path / "a" / "b" / "libkin", ignore=shutil.ignore_patterns("_lib"))
    env = dict(os.environ, PYTHONPATH=str(tmp_path / "a" / "b"), LIBKIN_LIBRARY=str(tmp_path / "none.so"))
    r = subprocess.run([sys.executable, "-m", "libkin", "--version"], env=env, capture_output=True, text=True,
                       timeout=60, cwd=tmp_path)
    assert r.returncode == 1 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.startswith("libkin: could not load") and "none.so" in r.stderr
    r = subprocess.run([sys.executable, "-c", "import libkin"], env=env, capture_output=True, text=True,
                       timeout=60, cwd=tmp_path)
    assert r.returncode == 1 and "ImportError" in r.stderr


def pathlib_package():
    import pathlib

    return pathlib.Path(libkin.__file__).parent
