"""Where a run's limits bit (max_nodes, time_limit, max_length): one
sentence each saying how far it got and which option lifts it, printed by
`libkin explore`, written in report.md and in the viewer page's header."""
from __future__ import annotations

import math
from typing import Any, Dict

from . import model as _atlas
from . import tasks

# the default node limit: the depth bounds a run (no documented run comes
# near it: the hexagonal sail's whole graph, to depth 6, has about 27,000
# nodes); before, 200 stopped `libkin explore sail:6:2 --depth 2` at depth 1
MAX_NODES = 1_000_000



def _f(v: Any, fmt: str = ".4g") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, fmt)


def limits_hit(atlas: _atlas.Atlas) -> Dict[str, str]:
    """Where the run's limits bit: for each of max_nodes, time_limit and
    max_length that stopped part of the run, one sentence saying how far it
    got and which option lifts it (`libkin explore` prints them on stderr)."""
    se, nodes, out = atlas.settings, atlas.nodes, {}
    deepest = f" of {se['depth']}" if se.get("depth") is not None else ""
    found = f"{len(nodes):,} node{'s' if len(nodes) != 1 else ''} found"
    skipped = [n for n in nodes if n.status == "not expanded: max_nodes reached"]
    if skipped:
        d = min(n.depth for n in skipped)
        out["max_nodes"] = (f"stopped at depth {d}{deepest}: --max-nodes {se.get('max_nodes')} reached ({found}; "
                            f"{len(skipped):,} bifurcation{'s' if len(skipped) > 1 else ''} not expanded); "
                            f"raise --max-nodes to go deeper")
    late = [n for n in nodes if "time limit reached" in n.status]
    if late or atlas.stats.get("stopped_by") == "time_limit":
        d = min((n.depth for n in late), default=max((n.depth for n in nodes), default=0))
        out["time_limit"] = (f"stopped at depth {d}{deepest}: --time-limit {_f(se.get('time_limit'), 'g')} s "
                             f"reached ({found}; {len(late):,} not expanded or not all followed); the atlas so far "
                             f"is partial: raise --time-limit, or continue with --resume")
    budget = sum(1 for e in atlas.edges if e.event == tasks.BUDGET)
    if budget:
        out["max_length"] = (f"{budget:,} of {len(atlas.edges):,} paths ended at the path-length budget "
                             f"(--max-length {_f(se.get('max_length'))}) before any event; raise --max-length to "
                             f"follow them further")
    return out
