"""Loading is bounded in time and memory, not only in bytes (issue 39 item 6).

A model under the 64 MiB byte cap once cost the Python loader minutes of CPU
and gigabytes before it was refused: jsonschema walked every joint and bar
of a model whose counts alone exceeded the C library's matrix limits. Now a
JSON text above `LARGE_TEXT` bytes is checked by the C loader (fast, bounded)
instead of jsonschema, and so is a parsed model with more than `LARGE_COUNT`
joints and bars (issue 39 item 5: counts past the dense analysis's matrix
limits are no longer refused, the sparse mode needs no dense matrix). Timing
is not asserted (load could break it): the tests assert which path was taken
(jsonschema never runs on such input) and, in a subprocess, the peak memory.
"""
import json
import resource
import subprocess
import sys

import numpy as np
import pytest

from libkin import load_model
from libkin.assembly import _json
from libkin.errors import ModelFormatError
from libkin.io.model_json import parse, read_json


def lattice(n, label_pad=0):
    """An n x n 2D grid: 3 bars a joint (right, up, diagonal), bottom row fixed."""
    joints = [{"index": i * n + j, "label": f"J{i * n + j}" + "x" * label_pad,
               "xyz": [j + 0.125, i + 0.375], "free": [i > 0, i > 0]} for i in range(n) for j in range(n)]
    bars = [{"index": 0, "joints": [i * n + j, (i + a) * n + j + b], "length": 1.4142135623730951 if a and b else 1.0}
            for i in range(n) for j in range(n) for a, b in ((0, 1), (1, 0), (1, 1)) if i + a < n and j + b < n]
    for k, b in enumerate(bars):
        b["index"] = k
    return {"name": "lattice", "dimension": 2, "joints": joints, "bars": bars}


@pytest.fixture
def no_schema(monkeypatch):
    """jsonschema must not run: the loader's cheap checks decide."""
    def refuse():
        raise AssertionError("jsonschema ran")
    _json._parse_text.cache_clear()
    monkeypatch.setattr(_json, "_validator", refuse)
    yield
    _json._parse_text.cache_clear()


# 125 x 125: 15 625 joints, 46 500 bars > 46 340 (nb * nb > INT_MAX): ~2.6 MB of text
OVER = lattice(125)
NB_OVER = len(OVER["bars"])


def test_past_dense_limit_file_loads_without_schema(tmp_path, no_schema):
    """nb * nb > INT_MAX: once refused (the dense matrices' limit), now made
    (the sparse mode analyses it; the dense analysis is refused then)."""
    assert NB_OVER > 46340
    path = tmp_path / "over.json"
    path.write_text(json.dumps(OVER))
    assert path.stat().st_size > _json.LARGE_TEXT
    a = load_model(str(path))
    assert a.nbars == NB_OVER and a.njoints == 125 * 125
    assert read_json(json.dumps(OVER))[2].shape == (NB_OVER, 2)


def test_large_dict_checked_by_c_not_schema(no_schema):
    got = parse(OVER)
    assert got[2].shape == (NB_OVER, 2)
    # free coordinates too: 3D, 21 000 joints all free = 63 000 > 46 340, one bar
    doc = {"dimension": 3, "joints": [{"xyz": [i, 0, 0]} for i in range(21000)], "bars": [{"joints": [0, 1]}]}
    assert parse(doc)[1].shape == (21000, 3)
    # and its verdict on a malformed one is the C loader's
    bad = json.loads(json.dumps(OVER))
    bad["bars"][7]["joints"] = [0, 10 ** 6]
    with pytest.raises(Exception) as exc:
        parse(bad)
    assert exc.type.__name__ != "AssertionError"


def test_within_limits_dict_still_schema_checked():
    doc = lattice(3)
    doc["joints"][4]["xyz"] = [1, "a"]
    with pytest.raises(ModelFormatError, match=r"joints\[4\]\.xyz"):
        parse(doc)


def test_large_valid_text_checked_by_c_same_model(no_schema):
    """A valid text above LARGE_TEXT (long labels) is checked by the C loader,
    not jsonschema, and read to the same model as the small path."""
    doc = lattice(4, label_pad=_json.LARGE_TEXT // 10)
    text = json.dumps(doc)
    assert len(text) > _json.LARGE_TEXT
    got = read_json(text)
    name, coords, bars, fixed, lengths, labels = got
    assert name == "lattice" and labels == [j["label"] for j in doc["joints"]]
    np.testing.assert_array_equal(coords, [j["xyz"] for j in doc["joints"]])
    np.testing.assert_array_equal(bars, [b["joints"] for b in doc["bars"]])
    np.testing.assert_array_equal(fixed, [[not f for f in j["free"]] for j in doc["joints"]])
    np.testing.assert_array_equal(lengths, [b["length"] for b in doc["bars"]])
    a = load_model(text)
    assert a.labels == labels and a.name == "lattice" and a.nbars == len(doc["bars"])


def test_large_malformed_text_refused_by_c(no_schema):
    doc = lattice(4, label_pad=_json.LARGE_TEXT // 10)
    doc["joints"][5]["xyz"] = [1, "a"]
    with pytest.raises(ModelFormatError):
        read_json(json.dumps(doc))


PEAK = """
import resource, sys
from libkin import load_model
a = load_model(sys.argv[1])
print("loaded:", a.nbars, file=sys.stderr)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="ru_maxrss in KiB on Linux")
def test_past_dense_limit_file_peak_memory(tmp_path):
    """Loading a file past the dense limits costs memory proportional to its
    size (under 20x, above what importing libkin and numpy costs): no dense
    workspace is made."""
    path = tmp_path / "over.json"
    path.write_text(json.dumps(OVER))
    base = subprocess.run([sys.executable, "-c", "import resource, libkin; "
                           "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)"],
                          capture_output=True, text=True, check=True)
    out = subprocess.run([sys.executable, "-c", PEAK, str(path)], capture_output=True, text=True, check=True)
    assert f"loaded: {NB_OVER}" in out.stderr
    grown = (int(out.stdout) - int(base.stdout)) * 1024
    assert grown < 20 * path.stat().st_size, (grown, path.stat().st_size)
