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


def test_options_are_initialised_whole():
    # the plain *_default symbols fill only a struct's first layout
    # (docs/abi.md): the package fills its structs through the sized
    # *_init forms, every field included
    src = pathlib.Path(libkin.__file__).resolve().parent
    for f in src.rglob("*.py"):
        assert not re.search(r"lib\.kin_\w+_default\(", f.read_text()), f
    for ctype in ("kin_locate_options", "kin_follow_options", "kin_homotopy_options"):
        p = _lib.default_struct(ctype)
        assert p.size == _lib.ffi.sizeof(ctype)
    o = _lib.default_struct("kin_options")
    assert o.size == _lib.ffi.sizeof("kin_options") and o.rank_tol == 1e-9
    s = _lib.default_struct("kin_sail_params", 6, 2)
    assert s.n_sides == 6 and s.side == 1.0
    assert _lib.lib.kin_options_init(_lib.ffi.new("kin_options *"), 3) == _lib.lib.KIN_EINVAL
