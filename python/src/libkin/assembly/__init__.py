"""The Assembly class and its result types.

`Assembly` (core.py) is composed of one class per concern, each defining its
methods in its own body: the handle, model and first-order analysis
(`_base.AssemblyBase`, `Analysis`), path following (`_path.PathMixin`,
`Options`, `StepInfo`), the paths out of a bifurcation
(`_branching.BranchingMixin`, `Branches`, `BranchPath`, `solve_quadrics`;
the canonical order and sign of the solutions, `_canonical.canonical_order`)
and locating bifurcations (`_locating.LocatingMixin`, `LocateInfo`,
`FollowEvent`, `BranchLines`); its JSON form is `_json.py`.

This package depends only on `libkin._native` and `libkin.errors`; the file
formats (`libkin.io`) and everything else build on it.
"""
from ._base import Analysis
from ._branch_lines import BranchLines
from ._branching import BranchPath, Branches, solve_quadrics
from ._canonical import canonical, canonical_order
from ._locating import FollowEvent, LocateInfo, SingularProof
from ._path import Options, StepInfo
from .core import Assembly

__all__ = ["Assembly", "Analysis", "StepInfo", "Options", "BranchPath", "Branches", "LocateInfo", "FollowEvent",
           "SingularProof", "solve_quadrics", "BranchLines", "canonical", "canonical_order"]
