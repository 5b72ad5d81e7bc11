"""`libkin explore` after a partial install: it refuses before any work, in
one line naming the extra, and never turns symmetry detection off silently."""
import sys

import pytest

from libkin.atlas import explorer
from libkin.cli import main
from libkin.errors import LimitError


@pytest.mark.parametrize("module", ["networkx", "matplotlib"])
def test_explore_refuses_without_an_extra(tmp_path, capsys, monkeypatch, module):
    started = []
    monkeypatch.setattr(explorer, "explore", lambda *a, **k: started.append(1))
    monkeypatch.setitem(sys.modules, module, None)  # as if not installed
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--depth", "1", "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert not started and not out.exists()  # no work done, nothing written
    assert len(err.strip().splitlines()) == 1 and module in err and "libkin[" in err


def test_symmetry_detection_off_is_said(tmp_path, capsys, monkeypatch):
    """A structure whose symmetry search gives up is explored without
    symmetries, and the report and the command say so."""
    def give_up(*args, **kwargs):
        raise LimitError("more automorphisms than the search enumerates")
    monkeypatch.setattr(explorer, "symmetries_at", give_up)
    out = tmp_path / "atl"
    assert main(["explore", "threebar:RC", "--depth", "1", "--out", str(out), "--quiet"]) == 0
    said = capsys.readouterr().out
    assert "more automorphisms than the search enumerates" in said
    assert "more automorphisms than the search enumerates" in (out / "report.md").read_text()


def test_documented_install_brings_what_explore_needs():
    """The install line of each README names extras that bring every module
    the atlas's files need."""
    import pathlib
    import re
    from libkin.atlas.report import OUTPUT_MODULES
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    root = pathlib.Path(__file__).resolve().parents[2]
    extras = tomllib.loads((root / "python" / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    for readme in ("README.md", "python/README.md"):
        line = re.search(r"pip install '\./python\[([\w,]+)\]'", (root / readme).read_text())
        assert line, readme
        brought = {re.split(r"[<>=\[ ]", dep)[0] for x in line.group(1).split(",") for dep in extras[x]}
        assert set(OUTPUT_MODULES) <= brought, (readme, brought)
