import pathlib

import pytest

# the paper's models ship with the repository (copies of ../shared/models,
# which a fresh clone does not have)
MODELS = pathlib.Path(__file__).resolve().parents[2] / "examples" / "models"


@pytest.fixture
def shared_models():
    assert MODELS.is_dir(), f"{MODELS} is missing"
    return MODELS
