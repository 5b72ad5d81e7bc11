"""Plots with matplotlib (Agg): structures, singular values along a path and
path animations in a plane (draw2d.py; the old module libkin.plot's names
are exported here), and 3D drawings, small multiples and animations
(draw3d.py); the pictures of `libkin follow`, with legends and supports,
3D models in 3D (follow.py)."""
from . import draw3d, follow
from .draw2d import _plt, animate, branch_directions, draw, pyplot, singular_values

__all__ = ["draw", "singular_values", "branch_directions", "animate", "pyplot", "draw3d", "follow"]
