"""File formats: the JSON model format (model_json.py) and FOLD (fold/).

Both read into and write from `libkin.Assembly`: this package builds on
`libkin.assembly`, which never imports it.
"""
from .fold import FoldAssembly, check_fold, read_fold, write_fold
from .model_json import load_json, load_model, to_json

__all__ = ["load_json", "load_model", "to_json", "read_fold", "write_fold", "check_fold", "FoldAssembly"]
