"""The version of libkin: the loaded C library's (``kin_version_string()``),
which is also the version of this package.

A module of its own so that code below the package root (the studies' cache
keys, the command line) can name the version without importing the root and
everything it re-exports; ``libkin.__version__`` is this same string.
"""
from ._native._lib import c_string, lib

__version__: str = c_string(lib.kin_version_string())

__all__ = ["__version__"]
