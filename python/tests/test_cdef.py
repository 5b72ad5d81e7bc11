"""The cffi declarations are generated from the C headers and must not drift."""
import importlib.util
import pathlib
import re

import libkin
from libkin._native import _cdef, _lib

TOOLS = pathlib.Path(__file__).resolve().parents[1] / "tools" / "gen_cdef.py"
INCLUDE = pathlib.Path(__file__).resolve().parents[2] / "include"


def _gen():
    spec = importlib.util.spec_from_file_location("gen_cdef", TOOLS)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_committed_cdef_matches_headers():
    gen = _gen()
    assert gen.OUT.read_text() == gen.generate(), "run python/tools/gen_cdef.py"


def test_every_public_function_is_declared_and_loadable():
    names = set()
    for h in INCLUDE.glob("libkin/*.h"):
        names |= set(re.findall(r"KIN_API\s+[\w\s\*]+?\b(kin_\w+)\s*\(", h.read_text()))
    assert len(names) > 30
    for n in sorted(names):
        assert n in _cdef.CDEF, n
        assert callable(getattr(libkin.lib, n)), n


def test_status_enum_values_match_library_messages():
    for code, name in enumerate(_cdef.STATUS_NAMES):
        assert getattr(libkin.lib, name) == code
        msg = _lib.ffi.string(libkin.lib.kin_strerror(code)).decode()
        assert msg == _cdef.STATUS_MESSAGES[name]
