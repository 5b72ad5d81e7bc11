"""Symmetry: the structure's symmetry group (automorphisms.py: the bar
graph's automorphisms realised by orthogonal maps, at a configuration, and
their action on the mechanisms) and the solar-sail family's cyclic symmetry
with the second-order analysis restricted to motions that keep it
(cyclic.py; the old module libkin.symmetry's names are exported here).
"""
from .automorphisms import (MAX_CANDIDATES, Symmetry, c_mechanism_group, c_symmetries, detect_symmetries,
                            graph_automorphisms, invariant_subspace, mechanism_group, same_symmetry, symmetries_at)
from .cyclic import FloatArray, restricted_quadrics, sail_rotation, symmetric_solutions, symmetric_subspace

__all__ = ["sail_rotation", "symmetric_subspace", "restricted_quadrics", "symmetric_solutions", "FloatArray",
           "Symmetry", "graph_automorphisms", "symmetries_at", "detect_symmetries", "c_symmetries", "same_symmetry",
           "invariant_subspace", "mechanism_group", "c_mechanism_group", "MAX_CANDIDATES"]
