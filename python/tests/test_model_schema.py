"""The model format's JSON Schema (libkin/assembly/model.schema.json, draft 2020-12)
against the C loader on the corpus tests/models/: every good file passes the
schema (as any validator reads it), and for every file the verdict of the
schema plus the checks a schema cannot say (model_json._problems) is the C
loader's (kin_assembly_load): malformed (KIN_EFORMAT) or not."""
import json
import pathlib

import jsonschema
import pytest

import libkin
from libkin import KinError, ModelFormatError
from libkin.assembly import _json as model_json  # the format's code: schema, validator, checks

CORPUS = pathlib.Path(__file__).resolve().parents[2] / "tests" / "models"
GOOD = sorted((CORPUS / "good").glob("*.json"))
BAD = sorted((CORPUS / "bad").glob("*.json"))
ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_schema_is_a_draft_2020_12_schema_in_the_package():
    s = model_json.schema()
    assert s["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    jsonschema.Draft202012Validator.check_schema(s)
    assert (pathlib.Path(model_json.__file__).parent / model_json.SCHEMA_FILE).is_file()
    assert "model.schema.json" in (ROOT / "docs" / "model_format.md").read_text()


@pytest.mark.parametrize("path", GOOD, ids=lambda p: p.name)
def test_good_files_pass_the_schema(path):
    doc = json.loads(path.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator(model_json.schema()).validate(doc)  # any validator
    assert model_json._validator().is_valid(doc)  # integers as literals
    assert not model_json._problems(doc)


def c_verdict(path):
    try:
        libkin.load_model(str(path), engine="c").close()
    except ModelFormatError:
        return "malformed"
    except KinError:
        return "well-formed"  # refused by the assembly's rules (self bar, duplicate bar, ...)
    return "well-formed"


def schema_verdict(path):
    """malformed if the text is not JSON as both loaders read it, else what
    the schema and the checks a schema cannot say find"""
    try:
        doc = json.loads(path.read_bytes().decode("utf-8"))
        model_json._check_text(doc)
    except (UnicodeDecodeError, ValueError, RecursionError):  # ModelFormatError is a ValueError
        return "malformed", False
    return ("malformed" if model_json._problems(doc) else "well-formed"), model_json._validator().is_valid(doc)


@pytest.mark.parametrize("path", GOOD + BAD, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_schema_and_c_loader_agree(path):
    verdict, schema_alone = schema_verdict(path)
    assert verdict == c_verdict(path)
    if path.parent.name == "good":
        assert schema_alone and verdict == "well-formed"
    if path.name.startswith("EFORMAT__"):
        assert verdict == "malformed"
    elif path.parent.name == "bad":  # refused by the assembly's rules, which are not the format's
        assert verdict == "well-formed"


def test_the_schema_alone_finds_most_bad_files():
    """Most malformed files break the schema itself; the rest break what a
    schema cannot say (index = position, joint index range, 64-bit
    integers, non-finite numbers) or are not JSON as both loaders read it."""
    caught = []
    for path in BAD:
        if not path.name.startswith("EFORMAT__"):
            continue
        try:
            doc = json.loads(path.read_bytes().decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError):
            continue
        caught.append(not model_json._validator().is_valid(doc))
    assert sum(caught) >= 0.7 * len(caught)
