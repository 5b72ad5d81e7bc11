"""The study keeps its solved flat state (issue 22 item 2): a rerun with the
same model does not solve it again and reports the same numbers."""
import json

from libkin import Assembly
from libkin.studies import flatcache, sailstudy
from libkin.symmetry import mechanism_group


def _counting(monkeypatch):
    calls = []
    real = flatcache.solve_quadrics

    def solve(*a, **k):
        calls.append(1)
        return real(*a, **k)
    monkeypatch.setattr(flatcache, "solve_quadrics", solve)
    return calls


def _complete_line(out):
    return [ln for ln in (out / "report.md").read_text().splitlines() if "Complete solver over all" in ln]


def test_a_rerun_of_the_study_does_not_solve_the_flat_state_again(tmp_path, monkeypatch):
    calls = _counting(monkeypatch)
    out = tmp_path / "study"
    first = sailstudy.hexagonal_study(6, 1, complete=True, progress=False, out=out, map_depth=1)
    assert len(calls) == 1
    assert flatcache.cache_path(out).exists()
    line = _complete_line(out)
    again = sailstudy.hexagonal_study(6, 1, complete=True, progress=False, out=out, map_depth=1)
    assert len(calls) == 1  # taken from the cache
    assert again["flat"]["complete"] == first["flat"]["complete"]
    assert json.loads((out / "summary.json").read_text())["flat"]["complete"] == first["flat"]["complete"]
    assert line and _complete_line(out) == line  # the same numbers in report.md


def test_the_cache_is_kept_per_model(tmp_path, monkeypatch):
    calls = _counting(monkeypatch)
    out = tmp_path / "study"
    a, b = Assembly.sail(4, 1), Assembly.sail(6, 1)
    ga, gb = mechanism_group(a, method="c"), mechanism_group(b, method="c")
    ra = flatcache.flat_solve(a, ga, 1, False, out)
    assert len(calls) == 1 and not ra[2]
    assert flatcache.flat_solve(a, ga, 1, False, out)[2] and len(calls) == 1
    rb = flatcache.flat_solve(b, gb, 1, False, out)  # another model: solved, and the cache replaced
    assert len(calls) == 2 and not rb[2] and rb[1]["paths"] != ra[1]["paths"]
    assert flatcache.flat_solve(b, gb, 1, False, out)[2] and len(calls) == 2
    flatcache.cache_path(out).write_text("{not json")  # a damaged cache: solved again
    assert not flatcache.flat_solve(b, gb, 1, False, out)[2] and len(calls) == 3
    assert not flatcache.flat_solve(a, ga, 1, False, None)[2] and len(calls) == 4  # no out: no cache
