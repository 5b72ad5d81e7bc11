"""The old flat module names, kept working with a DeprecationWarning.

Until 0.3 the package was one flat folder (libkin/model_json.py,
libkin/atlas_tasks.py, ...). `ALIASES` maps each old dotted name to the
module that now holds its code; `install()` (run by libkin/__init__.py) puts
a finder at the front of sys.meta_path that answers an import of an old name
with the new module itself (the same object, so ``libkin.fold.read_fold is
libkin.io.fold.read_fold``), warning DeprecationWarning once per process and
name. It imports nothing of libkin: the new module is imported by name when
an old one is asked for.
"""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import os
import sys
import types
import warnings
from typing import Dict, Optional, Sequence

#: old dotted name -> new dotted name
ALIASES: Dict[str, str] = {
    "libkin.model_json": "libkin.io.model_json",
    "libkin.fold": "libkin.io.fold",
    "libkin.atlas_index": "libkin.atlas.index",
    "libkin.atlas_tasks": "libkin.atlas.tasks",
    "libkin.atlas_cli": "libkin.atlas.cli",
    "libkin.atlas_condense": "libkin.atlas.condense",
    "libkin.atlas_orbits": "libkin.atlas.orbits",
    "libkin.atlas_plot": "libkin.atlas.plot",
    "libkin.atlas_report": "libkin.atlas.report",
    "libkin.automorphisms": "libkin.symmetry.automorphisms",
    "libkin.homotopy_shards": "libkin.homotopy.shards",
    "libkin.sailstudy": "libkin.studies.sailstudy",
    "libkin.squarestudy": "libkin.studies.squarestudy",
    "libkin.sailmap": "libkin.studies.sailmap",
    "libkin.sailmeasure": "libkin.studies.sailmeasure",
    "libkin.studyfigures": "libkin.studies.studyfigures",
    "libkin.studyreport": "libkin.studies.studyreport",
    "libkin.draw3d": "libkin.plot.draw3d",
    # the private modules of the flat layout
    "libkin._cdef": "libkin._native._cdef",
    "libkin._lib": "libkin._native._lib",
    "libkin._arrays": "libkin._native._arrays",
    "libkin._progress": "libkin._native._progress",
    "libkin._startup": "libkin._native._startup",
    "libkin._base": "libkin.assembly._base",
    "libkin._path": "libkin.assembly._path",
    "libkin._locating": "libkin.assembly._locating",
    "libkin._branching": "libkin.assembly._branching",
}


_PACKAGE_INIT = os.path.join(os.path.dirname(__file__), "__init__.py")


def _caller_stacklevel() -> int:
    """The stacklevel of warnings.warn (called by our caller) that names the
    first frame outside this module, libkin/__init__.py and the import
    machinery: the importing code. warnings does not count the frames of
    importlib._bootstrap, so neither does this."""
    level, f = 1, sys._getframe(1).f_back
    while f is not None:
        name = f.f_code.co_filename
        if "importlib" in name and "_bootstrap" in name:  # skipped by warnings itself
            f = f.f_back
            continue
        level += 1
        if name not in (__file__, _PACKAGE_INIT) and "importlib" not in name:
            return level
        f = f.f_back
    return level


class _AliasLoader(importlib.abc.Loader):
    """Hands out the new module for the old name; the new module's own spec
    is kept (importlib sets __spec__ on the module it is given)."""

    def __init__(self, old: str, new: str) -> None:
        self.old, self.new = old, new
        self.target: Optional[types.ModuleType] = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        warnings.warn(f"{self.old} is deprecated: import {self.new}", DeprecationWarning,
                      stacklevel=_caller_stacklevel())
        self.target = importlib.import_module(self.new)
        self.spec = self.target.__spec__
        return self.target

    def exec_module(self, module: types.ModuleType) -> None:
        module.__spec__ = self.spec  # undo importlib's module.__spec__ = <the alias spec>


class AliasFinder(importlib.abc.MetaPathFinder):
    """Finds the old names of ALIASES (see the module docstring)."""

    def find_spec(self, fullname: str, path: Optional[Sequence[str]] = None,
                  target: Optional[types.ModuleType] = None) -> Optional[importlib.machinery.ModuleSpec]:
        new = ALIASES.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _AliasLoader(fullname, new))


def install() -> None:
    """Put the finder at the front of sys.meta_path (once)."""
    if not any(isinstance(f, AliasFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, AliasFinder())


def old_module(name: str) -> types.ModuleType:
    """libkin.<name> for an old flat name (libkin.__getattr__): the new module, with the warning."""
    full = f"libkin.{name}"
    if full not in ALIASES:
        raise AttributeError(f"module 'libkin' has no attribute {name!r}")
    return importlib.import_module(full)
