"""Errors, validation and lifetime at the Python/C boundary."""
import math

import numpy as np
import pytest

import libkin
from libkin import errors
from libkin._native import _cdef, _lib

TRI = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
TRI_BARS = np.array([[0, 1], [1, 2], [2, 0]])


def raises(cls, fn, *a, **k):
    with pytest.raises(cls) as ei:
        fn(*a, **k)
    assert isinstance(ei.value, libkin.KinError)
    return ei.value


def test_creation_errors_map_to_subclasses_with_code_and_detail():
    # a dimension other than 2 or 3 is caught in Python, before C
    with pytest.raises(errors.DimensionError, match="2 or 3"):
        libkin.Assembly(np.arange(12.0).reshape(3, 4), TRI_BARS)
    e = raises(errors.JointIndexError, libkin.Assembly, TRI, [[0, 5]])
    assert "bar 0" in str(e) and e.code == libkin.lib.KIN_EJOINT
    e = raises(errors.SelfBarError, libkin.Assembly, TRI, [[1, 1]])
    assert e.code == libkin.lib.KIN_ESELFBAR
    e = raises(errors.DuplicateBarError, libkin.Assembly, TRI, [[0, 1], [1, 0]])
    assert "bars 0 and 1" in str(e)
    raises(errors.GeometryError, libkin.Assembly, [[0, 0], [0, 0], [1, 1]], TRI_BARS)
    raises(errors.GeometryError, libkin.Assembly, [[0, 0], [1, math.nan], [1, 1]], TRI_BARS)
    raises(errors.GeometryError, libkin.Assembly, TRI, TRI_BARS, lengths=[1, -1, 1])
    raises(errors.NoFreeCoordinatesError, libkin.Assembly, TRI, TRI_BARS, fixed=np.ones((3, 2), bool))
    raises(errors.InvalidArgumentError, libkin.Assembly, TRI[:1], [[0, 0]])


def test_shapes_and_dtypes_are_checked_before_c():
    # wrong shapes are ValueErrors, wrong kinds of values TypeErrors; neither is a model-format error
    with pytest.raises(errors.InvalidArgumentError, match="bars: expected shape"):
        libkin.Assembly(TRI, [0, 1, 2])
    with pytest.raises(errors.DimensionError, match="coords"):
        libkin.Assembly(np.zeros((3, 5)), TRI_BARS)
    with pytest.raises(errors.ArgumentTypeError, match="expected integers"):
        libkin.Assembly(TRI, [[0, 1.5]])
    with pytest.raises(ValueError, match="fixed"):
        libkin.Assembly(TRI, TRI_BARS, fixed=np.zeros((2, 2), bool))
    with pytest.raises(errors.InvalidArgumentError, match="lengths"):
        libkin.Assembly(TRI, TRI_BARS, lengths=[1.0, 2.0])
    with pytest.raises(TypeError, match="coords: not an array"):
        libkin.Assembly([[0, 0], [1]], TRI_BARS)
    with pytest.raises(TypeError, match="non-numeric"):
        libkin.Assembly([["a", "b"]] * 3, TRI_BARS)
    # non-contiguous and other dtypes are accepted by copying, and give the same model
    big = np.zeros((3, 4))
    big[:, ::2] = TRI
    a = libkin.Assembly(big[:, ::2], TRI_BARS.astype(np.int64))
    assert np.array_equal(a.coords, TRI)
    a.close()


def test_caller_arrays_are_not_changed():
    c = TRI.copy()
    a = libkin.Assembly(c, TRI_BARS, fixed=[[1, 1], [0, 1], [0, 0]])
    a.coords = a.coords
    assert np.array_equal(c, TRI)


def test_step_errors_leave_state_and_raise():
    a = libkin.Assembly.threebar("RC")
    with pytest.raises(errors.AtBifurcationError):
        a.step(0.01)
    with pytest.raises(ValueError):
        a.step(float("nan"))
    with pytest.raises(errors.InvalidArgumentError, match="first-order mechanism"):
        a.set_direction([1.0, 0, 0, 0])
    with pytest.raises(errors.InvalidArgumentError, match="direction"):
        a.set_direction([0, 1.0])
    xyz = a.coords
    xyz[2, 0] = 0.5  # S1 is a support
    with pytest.raises(errors.InvalidArgumentError, match="fixed"):
        a.coords = xyz
    o = a.options
    o.rank_tol = 2.0
    with pytest.raises(errors.InvalidArgumentError, match="rank_tol"):
        a.options = o
    rigid = libkin.Assembly(TRI, TRI_BARS, fixed=[[1, 1], [1, 1], [0, 0]])
    with pytest.raises(errors.NoMechanismError):
        rigid.step()
    impossible = libkin.Assembly(TRI, TRI_BARS, fixed=[[1, 1], [1, 1], [0, 0]], lengths=[1, 1, 5])
    before = impossible.coords
    with pytest.raises(errors.NotConvergedError):
        impossible.relax(max_iter=10)
    assert np.array_equal(before, impossible.coords)


def test_closed_assembly_raises_and_double_close_is_safe():
    a = libkin.Assembly.threebar()
    a.close()
    a.close()
    with pytest.raises(errors.StateError, match="closed"):
        a.analyse()
    with libkin.Assembly.threebar() as b:
        assert b.nfree == 4
    with pytest.raises(errors.StateError):
        b.nfree


def test_every_status_has_a_class():
    for name in _cdef.STATUS_NAMES[1:]:
        cls = errors.error_class(getattr(libkin.lib, name))
        assert issubclass(cls, libkin.KinError) and cls.name == name


def test_library_lookup_failure_lists_every_place(monkeypatch):
    monkeypatch.setattr(_lib, "_candidates", lambda: iter([("env", "/nonexistent/libkin.so"),
                                                           ("system loader (find_library('kin'))", "libnotkin_xyz.so")]))
    with pytest.raises(ImportError) as ei:
        _lib._load()
    assert "/nonexistent/libkin.so" in str(ei.value) and "libnotkin_xyz.so" in str(ei.value)


def test_version_mismatch_is_refused(monkeypatch):
    assert libkin.lib.kin_version_number() == _cdef.VERSION_NUMBER
    monkeypatch.setattr(_lib, "VERSION_NUMBER", 99999)
    with pytest.raises(ImportError, match="version"):
        _lib._load()
