"""The model-file corpus tests/models/ (shared with tests/test_model_io.c):
the Python loader and the C loader (kin_assembly_load, through cffi) give the
same verdict for every file: good/*.json load, bad/CODE__what.json fail with
status KIN_CODE (a ModelFormatError counts as KIN_EFORMAT). Good files load
to the same model bit for bit in both, and a model written by either
language reads back bit for bit in the other."""
import json
import os
import pathlib

import numpy as np
import pytest

import libkin
from libkin import KinError, ModelFormatError
from libkin._native._lib import ffi, lib

CORPUS = pathlib.Path(__file__).resolve().parents[2] / "tests" / "models"
GOOD = sorted((CORPUS / "good").glob("*.json"))
BAD = sorted((CORPUS / "bad").glob("*.json"))


def status_name(code):
    return ffi.string(lib.kin_status_name(code)).decode()


def expected(path):
    return "KIN_OK" if path.parent.name == "good" else "KIN_" + path.name.split("__")[0]


def python_verdict(path):
    try:
        libkin.load_json(str(path)).close()
    except ModelFormatError:
        return "KIN_EFORMAT"
    except KinError as exc:
        return status_name(exc.code)
    return "KIN_OK"


def c_model(ptr):
    """The model of a C handle as numpy arrays (coords, fixed, bars, rest lengths)."""
    dim, nj, nb = lib.kin_dim(ptr), lib.kin_njoints(ptr), lib.kin_nbars(ptr)
    coords, fixed = np.empty((nj, dim)), np.empty((nj, dim), dtype=np.uint8)
    bars, lengths = np.empty((nb, 2), dtype=np.int32), np.empty(nb)
    lib.kin_get_coords(ptr, ffi.cast("double *", coords.ctypes.data))
    lib.kin_get_fixed(ptr, ffi.cast("unsigned char *", fixed.ctypes.data))
    lib.kin_get_bars(ptr, ffi.cast("int *", bars.ctypes.data))
    lib.kin_get_rest_lengths(ptr, ffi.cast("double *", lengths.ctypes.data))
    return coords, fixed.astype(bool), bars, lengths


def python_model(asm):
    return asm.coords, np.asarray(asm.fixed, dtype=bool), np.asarray(asm.bars), asm.rest_lengths


def c_load(path=None, text=None):
    """(status name, message, model arrays or None) of the C loader."""
    out, err = ffi.new("kin_assembly **"), ffi.new("char[512]")
    if text is None:
        rc = lib.kin_assembly_load(os.fsencode(path), out, err, 512)
    else:
        data = text.encode("utf-8", "surrogatepass")
        rc = lib.kin_assembly_load_string(data, len(data), out, err, 512)
    model = None
    if out[0] != ffi.NULL:
        model = c_model(out[0])
        lib.kin_assembly_free(out[0])
    assert (rc == 0) == (model is not None)
    return status_name(rc), ffi.string(err).decode(), model


def assert_same(m1, m2):
    """Bit for bit (tobytes keeps the sign of zero)."""
    for a, b in zip(m1, m2):
        assert a.shape == b.shape
        assert np.ascontiguousarray(a, dtype=b.dtype).tobytes() == np.ascontiguousarray(b).tobytes()


def test_corpus_size():
    assert len(GOOD) >= 10 and len(BAD) >= 20
    for path in BAD:  # every bad file names a real status
        assert hasattr(lib, expected(path)), path.name


@pytest.mark.parametrize("path", GOOD + BAD, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_same_verdict(path):
    want = expected(path)
    c_status, c_message, _ = c_load(path)
    assert python_verdict(path) == want
    assert c_status == want, c_message
    if want != "KIN_OK":
        assert c_message  # C says why


@pytest.mark.parametrize("path", GOOD, ids=lambda p: p.name)
def test_good_models_agree_bit_for_bit(path):
    _, _, from_c = c_load(path)
    with libkin.load_json(str(path)) as asm:
        assert_same(python_model(asm), from_c)
        # Python writes, C reads
        _, _, back = c_load(text=json.dumps(asm.to_json()))
        assert_same(back, from_c)
        # C writes, Python reads
        text = ffi.new("char **")
        assert lib.kin_assembly_save_string(asm._p, b"from C", text, ffi.NULL, ffi.NULL, 0) == 0
        try:
            saved = ffi.string(text[0]).decode()
        finally:
            lib.kin_free_string(text[0])
    with libkin.load_json(saved) as again:
        assert_same(python_model(again), from_c)
        assert again.name == "from C"


def _verdicts(text):
    """(C status name, Python status name) for a model given as text."""
    c_status = c_load(text=text)[0]
    try:
        libkin.load_json(text).close()
        py_status = "KIN_OK"
    except ModelFormatError:
        py_status = "KIN_EFORMAT"
    except KinError as exc:
        py_status = status_name(exc.code)
    return c_status, py_status


def test_prefixes_and_mutants_same_verdict():
    """Every prefix of a small model, and seeded random edits of a few good
    files (characters replaced, deleted, inserted): both loaders agree."""
    import random
    rng = random.Random(20261123)
    pieces = list('{}[]",:0123456789-+.eE ntfrualsx\\') + [
        "true", "false", "null", "1e400", "-1", "2.0", "\\u0000", "\\ud800", "[[[["]
    cases = []
    base = (CORPUS / "good" / "threebar_RC.json").read_text()
    cases += [base[:i] for i in range(1, len(base))]
    for name in ("threebar_RA.json", "tetrahedron_3d_per_coordinate_supports.json",
                 "number_forms.json", "braced_square_redundant.json"):
        base = (CORPUS / "good" / name).read_text()
        for _ in range(150):
            s = list(base)
            for _ in range(rng.randint(1, 3)):
                p, op = rng.randrange(1, len(s)), rng.random()
                if op < 0.4:
                    s[p] = rng.choice(pieces)
                elif op < 0.7:
                    del s[p]
                else:
                    s.insert(p, rng.choice(pieces))
            cases.append("".join(s))
    # load_json reads text only when it starts with "{" (else it is a path)
    cases = [t for t in cases if t.startswith("{")]
    verdicts = [_verdicts(t) for t in cases]
    differ = [(t, v) for t, v in zip(cases, verdicts) if v[0] != v[1]]
    assert not differ, differ[:3]
    # some edits leave a valid model, most break it
    assert {v[0] for v in verdicts} >= {"KIN_OK", "KIN_EFORMAT"}


def _outcome(source, engine):
    """The model's arrays, or what kind of error loading it raised."""
    try:
        with libkin.load_model(source, engine=engine) as asm:
            return python_model(asm)
    except ModelFormatError:
        return "KIN_EFORMAT"
    except OSError:
        return "KIN_EIO"
    except KinError as exc:
        return status_name(exc.code)


@pytest.mark.parametrize("path", [GOOD[0], BAD[0], BAD[-1], CORPUS / "good" / "missing.json"],
                         ids=["good", "bad-first", "bad-last", "missing"])
def test_load_model_engines(path):
    """libkin.load_model(path or text, engine=...) gives the same model or
    the same kind of error from either loader."""
    sources = [str(path)]
    if path.exists() and path.read_text().startswith("{"):
        sources.append(path.read_text())
    for source in sources:
        py, c = _outcome(source, "python"), _outcome(source, "c")
        if isinstance(py, tuple):
            assert_same(py, c)
        else:
            assert py == c == expected(path) if path.exists() else py == c == "KIN_EIO"
    with pytest.raises(ValueError, match="engine"):
        libkin.load_model(str(path), engine="rust")
