"""libkin.version.blas(): the BLAS the C library runs on, as benchmarks print
it. Each case runs in a fresh interpreter, since OpenBLAS reads
OPENBLAS_CORETYPE and OPENBLAS_NUM_THREADS once, when it is loaded."""
import json
import os
import subprocess
import sys

import pytest

PROBE = "import json, libkin.version as v; print(json.dumps(v.blas()))"


def _blas(**env):
    out = subprocess.run([sys.executable, "-c", PROBE], env=dict(os.environ, **env), capture_output=True,
                         text=True, timeout=120, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_reports_the_kernel_and_threads_asked_for():
    b = _blas()
    if not b["openblas"]:
        pytest.skip(f"the C library's BLAS is not OpenBLAS ({b['library']})")
    assert os.path.exists(b["library"]) and b["kernel"] and b["threads"] >= 1
    forced = _blas(OPENBLAS_CORETYPE="Prescott", OPENBLAS_NUM_THREADS="1")
    assert forced["library"] == b["library"]
    assert forced["kernel"].lower() == "prescott" and forced["threads"] == 1


def test_line_names_the_kernel():
    from libkin.version import blas, blas_line
    b = blas()
    line = blas_line()
    assert line.startswith("[BLAS: ") and line.endswith("]")
    assert (b["kernel"] in line) if b["openblas"] else ("not OpenBLAS" in line)
