"""Bounded input (issue 22 item 5): the model and FOLD loaders refuse a file
above their size limit (the default and a raised one), never block on a FIFO
whose writer never closes nor read an endless device, raise only libkin's
classes on hostile FOLD text; write_fold never writes what read_fold rejects."""
import json
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from libkin import Assembly, load_model
from libkin._bounded import MAX_BYTES
from libkin.errors import FileAccessError, GeometryError, KinError, LimitError
from libkin.io import fold
from libkin.io.model_json import read_json

# examples per Hypothesis harness: 150 in the suite, more for a long run (tests/fuzz/README.md)
EXAMPLES_N = int(os.environ.get("LIBKIN_FUZZ_EXAMPLES", "150"))
EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "fold"
SMALL = {"dimension": 2, "joints": [{"xyz": [0, 0], "free": [False, False]}, {"xyz": [1, 0]}, {"xyz": [1, 1]},
                                    {"xyz": [0, 1], "free": [False, False]}],
         "bars": [{"joints": [0, 1]}, {"joints": [1, 2]}, {"joints": [2, 3]}]}
LOADERS = {
    "read_json": lambda p, **kw: read_json(p, **kw),
    "load_model_python": lambda p, **kw: load_model(p, **kw),
    "load_model_c": lambda p, **kw: load_model(p, engine="c", **kw),
    "read_fold": lambda p, **kw: fold.read_fold(p, **kw),
}


class _Timeout(Exception):
    pass


@pytest.fixture
def deadline():
    """A hang becomes a failure after 10 s."""
    def fire(signum, frame):
        raise _Timeout()
    old = signal.signal(signal.SIGALRM, fire)
    signal.alarm(10)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def _small_file(tmp_path, loader):
    p = tmp_path / ("small.fold" if loader == "read_fold" else "small.json")
    if loader == "read_fold":
        p.write_bytes((EXAMPLES / "fourbar.fold").read_bytes())
    else:
        p.write_text(json.dumps(SMALL))
    return p


@pytest.mark.parametrize("loader", sorted(LOADERS))
def test_size_limit_default_and_raised(tmp_path, loader):
    load = LOADERS[loader]
    small = _small_file(tmp_path, loader)
    n = small.stat().st_size
    load(small)
    load(small, max_bytes=n)
    with pytest.raises(LimitError):
        load(small, max_bytes=n - 1)
    big = tmp_path / "big.json"
    with open(big, "wb") as f:
        f.truncate(MAX_BYTES + 1)  # sparse: nothing is written
    t0 = time.monotonic()
    with pytest.raises(LimitError):
        load(big)
    assert time.monotonic() - t0 < 1.0  # refused before reading
    with pytest.raises(KinError) as exc:  # a raised limit reads it: zero bytes are not JSON
        load(big, max_bytes=MAX_BYTES + 1)
    assert not isinstance(exc.value, LimitError)


@pytest.mark.parametrize("loader", sorted(LOADERS))
def test_fifo_with_endless_writer_does_not_hang(tmp_path, loader, deadline):
    fifo = tmp_path / "endless.json"
    os.mkfifo(fifo)
    writer = subprocess.Popen([sys.executable, "-c",
                               "import sys\nf = open(sys.argv[1], 'w')\nwhile True: f.write('[' * 4096)",
                               str(fifo)])
    try:
        t0 = time.monotonic()
        with pytest.raises((FileAccessError, LimitError)):
            LOADERS[loader](fifo)
        # and again once the writer is attached and writing
        keep = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
        time.sleep(0.2)
        with pytest.raises((FileAccessError, LimitError)):
            LOADERS[loader](fifo)
        os.close(keep)
        assert time.monotonic() - t0 < 5.0
    finally:
        writer.kill()
        writer.wait()


@pytest.mark.parametrize("loader", sorted(LOADERS))
def test_endless_device_refused(loader, deadline):
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero")
    with pytest.raises((FileAccessError, LimitError)):
        LOADERS[loader]("/dev/zero")


HOSTILE = {
    "deep nesting": "[" * 200000 + "]" * 200000,
    "deep nesting in a field": '{"vertices_coords": ' + "[" * 100000 + "]" * 100000 + "}",
    "huge integer coordinate": '{"vertices_coords": [[1' + "0" * 400 + ', 0], [1, 0]], "edges_vertices": [[0, 1]]}',
    "integer of many digits": '{"vertices_coords": [[' + "9" * 5000 + ', 0], [1, 0]], "edges_vertices": [[0, 1]]}',
    "huge integer index": '{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1' + "0" * 400 + "]]}",
    "NaN literal": '{"vertices_coords": [[NaN, 0], [1, 0]], "edges_vertices": [[0, 1]]}',
    "Infinity length": '{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]], "edges_length": [Infinity]}',
    "huge float frame": '{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]], "file_frames": [1e999]}',
    "frame index huge": '{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]], "file_frames": '
                        '[{"frame_parent": 1' + "0" * 400 + ', "frame_inherit": true}]}',
    "coordinates far out": '{"vertices_coords": [[1e300, 0], [1, 0]], "edges_vertices": [[0, 1]]}',
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_fold_reader_raises_only_libkin_classes(tmp_path, name):
    text = HOSTILE[name]
    p = tmp_path / "hostile.fold"
    p.write_text(text)
    for source in (p, text) if text.startswith("{") else (p,):  # other text is taken for a path
        for frame in (0, 1):
            try:
                fold.read_fold(source, frame=frame)
            except KinError:
                pass


def test_fold_reader_bad_utf8(tmp_path):
    p = tmp_path / "bad.fold"
    p.write_bytes(b'{"file_title": "\xff\xfe", "vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]]}')
    with pytest.raises(KinError):
        fold.read_fold(p)


_json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=True) | st.text(max_size=5),
    lambda kids: st.lists(kids, max_size=4) | st.dictionaries(
        st.sampled_from(["vertices_coords", "edges_vertices", "faces_vertices", "edges_length", "file_frames",
                         "frame_parent", "frame_inherit", "edges_assignment", "vertices_libkin:fixed"]),
        kids, max_size=5),
    max_leaves=30)


@settings(max_examples=EXAMPLES_N, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(doc=_json_values, frame=st.integers(min_value=-1, max_value=3),
       faces=st.sampled_from(["rigid", "triangulate", "ignore"]))
def test_fold_reader_fuzz_documents(doc, frame, faces):
    """Hypothesis harness of the FOLD reader (the short run; docs/fuzzing.md
    gives the longer one): any JSON document raises only libkin's classes."""
    text = json.dumps(doc, allow_nan=True)
    for source in (doc, text) if isinstance(doc, dict) else ():
        try:
            fold.read_fold(source, frame=frame, faces=faces)
        except KinError:
            pass


@settings(max_examples=EXAMPLES_N, deadline=None)
@given(data=st.binary(max_size=200))
def test_fold_reader_fuzz_bytes(tmp_path_factory, data):
    p = tmp_path_factory.mktemp("fz") / "x.fold"
    p.write_bytes(b"{" + data)
    try:
        fold.read_fold(p)
    except KinError:
        pass


def _square(tmp_path):
    return fold.read_fold(EXAMPLES / "square_crease.fold")


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1e200])
def test_write_fold_refuses_what_read_fold_rejects(tmp_path, bad):
    a = _square(tmp_path)
    out = tmp_path / "out.fold"
    frames = [a.coords, a.coords.copy()]
    frames[1][0, 0] = bad
    with pytest.raises(GeometryError):
        fold.write_fold(out, a, path_coords=frames)
    assert not out.exists()


def test_write_fold_refuses_faces_read_fold_rejects(tmp_path):
    a = _square(tmp_path)
    out = tmp_path / "out.fold"
    with pytest.raises(KinError):
        fold.write_fold(out, a, faces=[[0, 1]])  # a face of two vertices
    assert not out.exists()
    with pytest.raises(KinError):
        fold.write_fold(out, a, faces=[[0, 1, a.njoints + 5]])  # a vertex out of range
    assert not out.exists()
    fold.write_fold(out, a)
    fold.read_fold(out)


def test_write_fold_refuses_a_file_read_fold_would_not_read(tmp_path, monkeypatch):
    from libkin.io.fold import writer
    monkeypatch.setattr(writer, "MAX_BYTES", 100)
    out = tmp_path / "out.fold"
    with pytest.raises(LimitError):
        fold.write_fold(out, _square(tmp_path))
    assert not out.exists()
