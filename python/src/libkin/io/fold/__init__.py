"""FOLD files in and out (https://github.com/edemaine/fold, doc/spec.md).

read_fold() (reader.py) turns a FOLD frame into an Assembly (a
`FoldAssembly`); write_fold() (writer.py) writes an assembly, or a path
followed from it, back; check_fold() checks a document against the spec's
structural rules. See reader.py for how faces and supports are read.
"""
from .reader import (FIXED_KEY, FOLD_SPEC, FoldAssembly, FoldDoc, FoldSource, FoldSourceArg, detect_resolution, read_fold,
                     resolve_frame)
from .writer import check_fold, graph_triangles, write_fold

__all__ = ["read_fold", "write_fold", "detect_resolution", "check_fold", "resolve_frame", "graph_triangles",
           "FoldAssembly", "FoldSource", "FoldDoc", "FoldSourceArg", "FOLD_SPEC", "FIXED_KEY"]
