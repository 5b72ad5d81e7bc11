"""The atlas: every path out of every bifurcation met, for any structure.

explore() (explorer.py) builds an `Atlas` (model.py: nodes, directed edges,
JSON and GraphML); the branches are followed as plain-data tasks (tasks.py)
on any executor (libkin.parallel), the second-order systems solved by
solving.py, nodes identified through index.py and, with symmetries, orbits.py.
condense.py, report.py and plot.py read an atlas; cli.py is `libkin explore`.
"""
from ..parallel import Progress, run_tasks
from .explorer import AUTO_MAX_S, Branch, explore
from .model import (BIFURCATION, FAILURE, LOCATION_FACTOR, MULTI_DOF, NEAR_MISS, NODE_KINDS, REGULAR, RIGID, SAME_TOL,
                    UNDECIDED, Atlas, Edge, Node, node_kind)
from .solving import OVERDETERMINED_TOL, SHARD_PATHS, complete_solve, solve_system

__all__ = ["explore", "Atlas", "Node", "Edge", "run_tasks", "solve_system", "complete_solve", "node_kind", "Progress",
           "Branch", "BIFURCATION", "REGULAR", "NEAR_MISS", "MULTI_DOF", "RIGID", "FAILURE", "UNDECIDED", "NODE_KINDS",
           "SAME_TOL", "LOCATION_FACTOR", "SHARD_PATHS", "OVERDETERMINED_TOL", "AUTO_MAX_S"]
