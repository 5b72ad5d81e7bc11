"""The store is verified, and its errors are ours (issue 39 item 3): a
resumed `libkin explore` never trusts its store (atlas/store.py). A record
that fails its checksum (edited, garbage, under another key, of another
type, or from a store written before checksums) is recomputed and counted,
and the atlas is the one an intact store gives; a store that cannot be used
(truncated, garbage, damaged, not a store's tables, a directory, a full disk
under it) is one line on stderr and exit 5 (cliargs.EXIT_STORE), never a
traceback, and in Python a StoreError (a KinError)."""
import errno
import json
import pathlib
import random
import shutil
import sqlite3

import pytest

from libkin import Assembly
from libkin.atlas import store as atlas_store
from libkin.atlas.model import Atlas
from libkin.cli import EXIT_STORE, main

MODEL = "sail:4:1"  # depth 1: 11 records (1 solve, 10 branches), 4 nodes, 32 directed paths


def _run(out, store, *more):
    return main(["explore", MODEL, "--depth", "1", "--out", str(out), "--store", str(store), "--quiet", *more])


def _graph(out):
    d = json.loads((pathlib.Path(out) / "atlas.json").read_text())
    return Atlas.from_dict(d), d["nodes"], d["edges"], d["stats"]


@pytest.fixture(scope="module")
def intact(tmp_path_factory):
    """A complete run's store (kept: --store given) and its atlas."""
    d = tmp_path_factory.mktemp("intact")
    assert _run(d / "atl", d / "store.sqlite") == 0
    return d / "store.sqlite", _graph(d / "atl")


@pytest.fixture
def store(tmp_path, intact):
    path = tmp_path / "store.sqlite"
    shutil.copy(intact[0], path)
    return path


def _edit(path, *sql):
    db = sqlite3.connect(str(path))
    with db:
        for s in sql:
            db.execute(*s) if isinstance(s, tuple) else db.execute(s)
    db.close()


def _branches(path):
    db = sqlite3.connect(str(path))
    rows = db.execute("SELECT key, value FROM results WHERE kind = 'follow_branch' ORDER BY seq").fetchall()
    db.close()
    return rows


def _resumed_same(tmp_path, capsys, intact, store, recomputed):
    """--resume on the hostile store: exit 0, the intact store's atlas, and
    the failed records counted (stats and the terminal line)."""
    out = tmp_path / "atl"
    rc = _run(out, store, "--resume")
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    ref, ref_nodes, ref_edges, _ = intact[1]
    at, nodes, edges, stats = _graph(out)
    assert at.same_as(ref, tol=0.0)
    assert nodes == ref_nodes and edges == ref_edges
    assert stats["store"]["recomputed"] == recomputed
    assert stats["store"]["reused"] + recomputed == 11
    assert f"store: {recomputed} recorded result" in cap.out and "recomputed" in cap.out
    return stats


def _refused(tmp_path, capsys, store, *more):
    """One line on stderr naming the store, exit 5 (a traceback would fail
    the test: main() would raise)."""
    rc = _run(tmp_path / "atl", store, *more)
    err = capsys.readouterr().err.strip()
    assert rc == EXIT_STORE, err
    assert len(err.splitlines()) == 1 and err.startswith("libkin: the store ") and str(store) in err, err
    assert "Traceback" not in err
    return err


# --- records that fail: recomputed, counted, the same atlas ---

def test_an_edited_record_is_recomputed(tmp_path, capsys, intact, store):
    key, value = _branches(store)[3]
    d = json.loads(value)
    d["length"] += 1.0  # today: exit 0 and an atlas with edges of the wrong length
    _edit(store, ("UPDATE results SET value = ? WHERE key = ?", (json.dumps(d), key)))
    _resumed_same(tmp_path, capsys, intact, store, 1)


def test_a_garbage_record_is_recomputed(tmp_path, capsys, intact, store):
    key, _ = _branches(store)[0]
    _edit(store, ("UPDATE results SET value = ? WHERE key = ?", ("{not json\x00\xff", key)))
    _resumed_same(tmp_path, capsys, intact, store, 1)


def test_a_record_of_another_type_is_recomputed(tmp_path, capsys, intact, store):
    key, _ = _branches(store)[1]
    _edit(store, ("UPDATE results SET value = 42 WHERE key = ?", (key,)))  # today: TypeError traceback
    _resumed_same(tmp_path, capsys, intact, store, 1)


def test_records_under_the_wrong_key_are_recomputed(tmp_path, capsys, intact, store):
    (k1, v1), (k2, v2) = _branches(store)[2:4]
    # the two results swapped, checksums and all: each is valid, under the other's key
    db = sqlite3.connect(str(store))
    d1, d2 = (db.execute("SELECT digest FROM results WHERE key = ?", (k,)).fetchone()[0] for k in (k1, k2))
    db.close()
    _edit(store, ("UPDATE results SET value = ?, digest = ? WHERE key = ?", (v2, d2, k1)),
          ("UPDATE results SET value = ?, digest = ? WHERE key = ?", (v1, d1, k2)))
    _resumed_same(tmp_path, capsys, intact, store, 2)


def test_an_edited_kind_or_checksum_is_recomputed(tmp_path, capsys, intact, store):
    (k1, _), (k2, _) = _branches(store)[4:6]
    _edit(store, ("UPDATE results SET kind = 'solve' WHERE key = ?", (k1,)),
          ("UPDATE results SET digest = ? WHERE key = ?", ("0" * 64, k2)))
    _resumed_same(tmp_path, capsys, intact, store, 2)


def test_a_store_written_before_checksums_is_recomputed(tmp_path, capsys, intact, store):
    # the schema of libkin before issue 39: no digest column
    _edit(store, "CREATE TABLE old AS SELECT key, kind, seq, value FROM results", "DROP TABLE results",
          "CREATE TABLE results (key TEXT PRIMARY KEY, kind TEXT NOT NULL, seq INTEGER NOT NULL, "
          "value TEXT NOT NULL)", "INSERT INTO results SELECT * FROM old", "DROP TABLE old")
    _resumed_same(tmp_path, capsys, intact, store, 11)
    db = sqlite3.connect(str(store))  # recorded again, with their checksums
    assert db.execute("SELECT COUNT(*) FROM results WHERE digest IS NULL").fetchone()[0] == 0
    db.close()


# --- stores that cannot be used: one line, exit 5 ---

def test_a_truncated_store_is_refused(tmp_path, capsys, store):
    data = store.read_bytes()
    store.write_bytes(data[: len(data) // 2])
    _refused(tmp_path, capsys, store, "--resume")


def test_a_store_of_garbage_bytes_is_refused(tmp_path, capsys, store):
    store.write_bytes(random.Random(1).randbytes(8192))
    _refused(tmp_path, capsys, store, "--resume")
    _refused(tmp_path, capsys, store)  # without --resume too: the file is not ours to overwrite


def test_a_damaged_page_is_refused(tmp_path, capsys, intact, store):
    data = bytearray(store.read_bytes())
    page = 4096
    for p in range(1, len(data) // page):  # garbage over the b-tree of every page but the header's
        data[p * page: p * page + 64] = random.Random(p).randbytes(64)
    store.write_bytes(bytes(data))
    _refused(tmp_path, capsys, store, "--resume")


def test_tables_that_are_not_a_store_are_refused(tmp_path, capsys, store):
    _edit(store, "DROP TABLE results", "CREATE TABLE results (key TEXT, other BLOB)")
    _refused(tmp_path, capsys, store, "--resume")


def test_a_directory_as_store_is_refused(tmp_path, capsys):
    d = tmp_path / "store.sqlite"
    d.mkdir()
    _refused(tmp_path, capsys, d)


def test_a_full_disk_under_the_store_is_refused(tmp_path, capsys, intact, monkeypatch):
    """SQLite's own SQLITE_FULL (what a full disk gives), in the middle of the
    run: the store may not grow past 6 pages. Then space is freed and
    --resume completes the run from what was recorded."""
    connect = sqlite3.connect

    def small(*a, **k):
        db = connect(*a, **k)
        db.execute("PRAGMA max_page_count = 6")
        return db
    monkeypatch.setattr(atlas_store.sqlite3, "connect", small)
    store = tmp_path / "store.sqlite"
    err = _refused(tmp_path, capsys, store)
    assert "recording a result" in err and "full" in err and "--resume" in err
    monkeypatch.undo()
    rc = _run(tmp_path / "atl", store, "--resume")
    assert rc == 0, capsys.readouterr().err
    ref, ref_nodes, ref_edges, _ = intact[1]
    at, nodes, edges, stats = _graph(tmp_path / "atl")
    assert at.same_as(ref, tol=0.0) and nodes == ref_nodes and edges == ref_edges
    assert stats["store"]["reused"] > 0 and stats["store"]["recomputed"] == 0


def test_enospc_creating_the_store_folder_is_refused(tmp_path, capsys, monkeypatch):
    mkdir, sub = pathlib.Path.mkdir, tmp_path / "sub"

    def full(self, *a, **k):
        if self == sub:
            raise OSError(errno.ENOSPC, "No space left on device", str(self))
        return mkdir(self, *a, **k)
    monkeypatch.setattr(pathlib.Path, "mkdir", full)
    err = _refused(tmp_path, capsys, sub / "store.sqlite")
    assert "No space left" in err


def test_the_python_api_raises_store_error(tmp_path, store):
    import libkin
    store.write_bytes(b"\x00garbage" * 100)
    with pytest.raises(atlas_store.StoreError) as e:
        libkin.explore(Assembly.sail(4, 1), depth=1, store=store, resume=True)
    assert isinstance(e.value, libkin.KinError) and str(store) in str(e.value)
