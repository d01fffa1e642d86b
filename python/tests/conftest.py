"""Shared fixtures of the Python module's tests (run by CTest: see python/CMakeLists.txt).

VELUM_EXE is the command line built with the module, VELUM_SOURCE_DIR the repository."""
import os
import subprocess
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("VELUM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE / "examples"


@pytest.fixture(scope="session")
def velum_exe():
    exe = os.environ.get("VELUM_EXE")
    if not exe:
        pytest.skip("VELUM_EXE not set (run through ctest)")
    return exe


@pytest.fixture(scope="session")
def run_cli(velum_exe):
    """Runs `velum ARGS...`; returns the CompletedProcess."""
    def run(*args):
        return subprocess.run([velum_exe, *map(str, args)], capture_output=True, text=True)
    return run


@pytest.fixture
def square():
    """The pressurised-square example (81 nodes, quad4, dynamic): fractions of a second."""
    return EXAMPLES / "pressurised-square" / "model.yaml"


@pytest.fixture
def cable():
    return EXAMPLES / "hanging-cable" / "model.yaml"
