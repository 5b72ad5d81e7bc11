import pathlib

import pytest

SHARED = pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "models"


@pytest.fixture
def shared_models():
    if not SHARED.is_dir():
        pytest.skip("../shared/models not present")
    return SHARED
