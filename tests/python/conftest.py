"""Shared fixtures of the Python package's tests (tests/python/CMakeLists.txt runs them).

The package comes from the build tree (PYTHONPATH=<build>/python);
PHEROMESH_BUILD_DIR and PHEROMESH_SOURCE_DIR say where the build and the
source tree are.
"""

import os
import subprocess
from pathlib import Path

import pytest

BUILD = Path(os.environ.get("PHEROMESH_BUILD_DIR", Path(__file__).resolve().parents[2] / "build"))
SOURCE = Path(os.environ.get("PHEROMESH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PROGRAM = BUILD / "bin" / "pheromesh"


def pheromesh_cli(*args: str, cwd=None) -> subprocess.CompletedProcess:
    """`pheromesh ARGS` of this build; fails the test with its output if it fails."""
    done = subprocess.run([str(PROGRAM), *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=300, cwd=cwd, check=False)
    assert done.returncode == 0, f"pheromesh {' '.join(args)} failed ({done.returncode}):\n{done.stdout}"
    return done


@pytest.fixture
def small_test() -> Path:
    return SOURCE / "scenarios" / "small-test.textproto"
