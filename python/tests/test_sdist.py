"""`python -m build --sdist python/` gives an sdist that carries the C
library's sources (the package builds them with CMake) and installs in a
fresh virtual environment. Slow (a pip install builds the library: minutes):
run with LIBKIN_TEST_SLOW=1, as the README's install snippets."""
import os
import pathlib
import subprocess
import sys
import tarfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SLOW = os.environ.get("LIBKIN_TEST_SLOW") == "1"


def _venv(path):
    subprocess.run([sys.executable, "-m", "venv", str(path)], check=True)
    return path / "bin"


@pytest.mark.skipif(not SLOW, reason="builds the sdist and installs it (minutes): LIBKIN_TEST_SLOW=1")
def test_sdist_carries_the_c_sources_and_installs(tmp_path):
    tools = _venv(tmp_path / "tools")
    subprocess.run([str(tools / "pip"), "install", "-q", "build"], check=True)
    dist = tmp_path / "dist"
    subprocess.run([str(tools / "python"), "-m", "build", "--sdist", str(ROOT / "python"), "--outdir", str(dist)],
                   check=True, capture_output=True)
    (sdist,) = dist.glob("libkin-*.tar.gz")
    with tarfile.open(sdist) as tf:
        names = {n.split("/", 1)[1] for n in tf.getnames() if "/" in n}
    c_sources = [p.relative_to(ROOT).as_posix() for d in ("libkin", "include", "cmake")
                 for p in (ROOT / d).rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    assert "csrc/CMakeLists.txt" in names
    assert {f"csrc/{n}" for n in c_sources} <= names
    # a fresh environment installs it (CMake builds the library) and imports it
    env_bin = _venv(tmp_path / "env")
    subprocess.run([str(env_bin / "pip"), "install", "-q", str(sdist)], check=True, capture_output=True)
    env = {k: v for k, v in os.environ.items() if k not in ("LIBKIN_LIBRARY", "PYTHONPATH")}
    r = subprocess.run([str(env_bin / "python"), "-c",
                        "import libkin; print(libkin.__file__); print(libkin.Assembly.threebar('RC').analyse().m_internal)"],
                       cwd=tmp_path, env=env, capture_output=True, text=True, check=True)
    where, m = r.stdout.split()
    assert str(tmp_path / "env") in where and m == "2"
