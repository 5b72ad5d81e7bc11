"""The package's build backend: scikit-build-core, with an sdist that
carries the C library's sources.

The package builds the library from the repository's top folder
(cmake.source-dir = ".."), which an sdist of python/ would leave out.
build_sdist copies the parts CMake needs (C_PARTS) into python/csrc for
the time of the build; a build from the sdist (PKG-INFO present) takes
its sources from there (the `if.from-sdist` override in pyproject.toml).
Everything else is scikit-build-core's."""
from __future__ import annotations

import pathlib
import shutil
from typing import Any, Dict, Optional

from scikit_build_core import build as _skbuild
from scikit_build_core.build import *  # noqa: F401,F403  (the PEP 517 hooks)

# what CMake reads to build the library, relative to the repository's top folder
C_PARTS = ("CMakeLists.txt", "cmake", "include", "libkin")
STAGE = "csrc"


def build_sdist(sdist_directory: str, config_settings: Optional[Dict[str, Any]] = None) -> str:
    here = pathlib.Path.cwd()  # the project folder, python/ (or an unpacked sdist)
    top, stage = here.parent, here / STAGE
    if (here / "PKG-INFO").exists() or stage.exists():  # an sdist's own copy: as it is
        return str(_skbuild.build_sdist(sdist_directory, config_settings))
    missing = [p for p in C_PARTS if not (top / p).exists()]
    if missing:
        raise FileNotFoundError(f"libkin sdist: {', '.join(missing)} not found in {top}")
    try:
        stage.mkdir()
        for part in C_PARTS:
            src = top / part
            if src.is_dir():
                shutil.copytree(src, stage / part, ignore=shutil.ignore_patterns("__pycache__", "*.o"))
            else:
                shutil.copy2(src, stage / part)
        return str(_skbuild.build_sdist(sdist_directory, config_settings))
    finally:
        shutil.rmtree(stage, ignore_errors=True)
