"""The atlas level by level (issue 24 item 6): explore() reports per level
what it expanded, followed and mapped and where the time went
(stats["levels"]); levels.by_depth() gives the per-depth table of a finished
atlas; a deeper run resumes a shallower run's store, reading its levels back."""
import libkin
from libkin.atlas import levels, store as atlas_store

MODEL = "sail:4:1"  # depth 2: 4 nodes, 32 + 12 directed paths; no new orbit at depth 2


def test_levels_count_every_branch_and_node():
    at = libkin.explore(MODEL, depth=2)
    rows = at.stats["levels"]
    assert [r["depth"] for r in rows] == [1, 2]
    assert sum(r["directed_branches"] for r in rows) == len(at.edges)
    for r in rows:
        assert r["followed"] + r["mapped"] == r["directed_branches"] and r["not_followed"] == 0
        assert min(r["enumerate_seconds"], r["follow_seconds"], r["merge_seconds"]) >= 0.0
    assert sum(r["followed"] for r in rows) == at.stats["branches_followed"]
    assert sum(r["mapped"] for r in rows) == at.stats["branches_mapped"]
    assert sum(r["new_nodes"] for r in rows) == len(at.nodes) - 1
    assert rows[0]["frontier"] == 1 and rows[0]["expanded"] == 1
    assert rows[1]["expanded"] == sum(1 for n in at.nodes if n.depth == 1 and n.expanded)


def test_by_depth_is_the_atlas_per_depth():
    at = libkin.explore(MODEL, depth=3)
    d = at.to_dict()
    table = levels.by_depth(d)
    assert [r["depth"] for r in table] == [1, 2]  # depth 2 reaches no new bifurcation: nothing to expand
    assert sum(r["directed_branches"] for r in table) == len(at.edges)
    assert sum(sum(r["events"].values()) for r in table) == len(at.edges)
    assert sum(r["new_nodes"] for r in table) == len(at.nodes) - 1
    assert sum(r["new_orbits"] for r in table) == len({n.orbit for n in at.nodes}) - 1
    assert table[1]["new_orbits"] == 0 and table[1]["back_to_earlier_nodes"] == table[1]["directed_branches"]
    for r, lv in zip(table, at.stats["levels"]):
        assert r["directed_branches"] == lv["directed_branches"] and r["new_nodes"] == lv["new_nodes"]


def test_a_deeper_run_resumes_a_shallower_store(tmp_path, monkeypatch):
    path = tmp_path / "run.sqlite"
    first = libkin.explore(MODEL, depth=1, store=path)
    recorded = first.stats["store"]["recorded"]
    deeper = libkin.explore(MODEL, depth=2, store=path, resume=True)
    assert deeper.stats["store"]["reused"] == recorded and deeper.stats["store"]["recorded"] > 0
    assert deeper.same_as(libkin.explore(MODEL, depth=2), tol=0.0)

    def never(*a, **k):
        raise AssertionError("computed again")
    monkeypatch.setattr(atlas_store, "run_tasks", never)  # and the shallower atlas again from the deeper store
    assert libkin.explore(MODEL, depth=1, store=path, resume=True).same_as(first, tol=0.0)
