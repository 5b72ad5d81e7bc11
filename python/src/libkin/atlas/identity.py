"""How clearly each branch end's node was decided (issue 35 item 4,
docs/atlas.md "Identification").

merge_level joins an end to a node when their distance d is within the
pair window w (model.pair_window: SAME_TOL plus each point's error bound).
That is a threshold, and a threshold can flip with rounding: an end at
d = 0.99 w on one machine may land at 1.01 w on another and start a node of
its own. So every decision is judged with a margin: it is *decided* when
the node it joins lies within w / IDENTITY_MARGIN and every other node
further than IDENTITY_MARGIN w (or, for an end that starts a node, every
node further than IDENTITY_MARGIN w). Anything else is *undecided*: the
merge still follows its rule (so the atlas has one shape), and the end is
listed with its numbers (the level row's "identity", the stats'
"identity_undecided") instead of being passed off as certain. The same
holds for a new node's symmetry identification (an image of an earlier
node, explorer.orbit_of): judge_image. The
margins are measured, not assumed: on the hexagonal sail's atlases the
ends of one node lie at d / w <= 2e-6 and the nearest other node at
d / w >= 1e3 (docs/atlas.md), so no real arrival is near either line.
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
from numpy.typing import NDArray

# a decision needs this factor of room on each side of the window
IDENTITY_MARGIN = 10.0


class Judge:
    """The identity margins of one level's ends (merge_level)."""

    def __init__(self) -> None:
        self.ends = 0
        self.images = 0                 # new nodes whose symmetry image was judged
        self.worst_join = 0.0           # the largest d / w of an end to the node it joined
        self.nearest_other = math.inf   # the smallest d / w of an end to a node it did not join
        self.undecided: List[Dict[str, Any]] = []

    def judge(self, ex: Any, k: int, located: float, joined: Optional[int], join_ratio: float,
              others: List[Tuple[float, Optional[int]]]) -> None:
        """End k (located to `located`) joined node `joined` (an earlier
        node's id; -1: one of this level's new nodes; None: it started one)
        at d / w = join_ratio; others: (d / w, node id or None for a new
        node of this level) of every other node within IDENTITY_MARGIN
        windows."""
        self.ends += 1
        if joined is not None:
            self.worst_join = max(self.worst_join, join_ratio)
        near, near_id = min(others, key=lambda o: o[0], default=(math.inf, None))
        self.nearest_other = min(self.nearest_other, near)
        if (joined is not None and join_ratio > 1.0 / IDENTITY_MARGIN) or near <= IDENTITY_MARGIN:
            self.undecided.append({"work": int(k), "joined": joined,
                                   "joined_ratio": None if joined is None else float(join_ratio),
                                   "nearest_other": near_id, "nearest_other_ratio": float(near),
                                   "located_tol": float(located)})

    def judge_image(self, ex: Any, node: Any) -> None:
        """A new node's symmetry identification (explorer.orbit_of: the node
        is g . k for the first earlier node k with g.k within its window):
        decided when the orbit it joined lies within 1/IDENTITY_MARGIN of
        the window and every other orbit's images further than
        IDENTITY_MARGIN windows (by orbit: an image of k is also one of
        every node of k's orbit)."""
        if len(ex.syms) <= 1:
            return
        best: Dict[int, Tuple[float, int]] = {}
        for i, j in ex.images.near(node.coords, lambda worst: IDENTITY_MARGIN * ex.pair_tol(node.located_tol, worst)):
            if i >= node.id:
                continue
            k = ex.nodes[i]
            r = ex._distance(ex.syms[j].apply(k.coords), node.coords) / ex.pair_tol(node.located_tol, k.located_tol)
            best[k.orbit] = min(best.get(k.orbit, (math.inf, -1)), (r, k.id))
        own = node.orbit if node.image_of is not None else None
        join = best.pop(own, (math.nan, -1))[0] if own is not None else math.nan
        self.images += 1
        near, near_id = min(best.values(), default=(math.inf, None))
        self.nearest_other = min(self.nearest_other, near)
        if own is not None:
            self.worst_join = max(self.worst_join, join)
        if (own is not None and join > 1.0 / IDENTITY_MARGIN) or near <= IDENTITY_MARGIN:
            self.undecided.append({"node": int(node.id), "image_of": None if own is None else node.image_of["node"],
                                   "image_of_ratio": None if own is None else float(join), "nearest_other": near_id,
                                   "nearest_other_ratio": float(near), "located_tol": float(node.located_tol)})

    def row(self) -> Dict[str, Any]:
        """The level row's "identity" entry."""
        return {"ends": self.ends, "images": self.images, "margin": IDENTITY_MARGIN, "worst_join_ratio": float(self.worst_join),
                "nearest_other_ratio": None if math.isinf(self.nearest_other) else float(self.nearest_other),
                "undecided": len(self.undecided), "undecided_ends": self.undecided}


def ratios(ex: Any, X: NDArray[np.float64], located: float, nodes: List[Any], index: Any) -> List[Tuple[float, Any]]:
    """(d / w, label) of every entry of `index` (labels into `nodes`, each
    with .coords/.located_tol, or a (coords, located) pair) within
    IDENTITY_MARGIN windows of X."""
    out: List[Tuple[float, Any]] = []
    for c in index.near(X, lambda worst: IDENTITY_MARGIN * ex.pair_tol(located, worst)):
        n = nodes[c]
        pt, tol = (n.coords, n.located_tol) if hasattr(n, "coords") else n
        out.append((ex._distance(X, pt) / ex.pair_tol(located, tol), c))
    return out
