"""Shared fixtures: the ldsm tool, a scratch folder and a small synthetic sequence rendered once."""
import os
import shutil
import subprocess
from pathlib import Path

import pytest


def ldsm_exe():
    exe = os.environ.get("LDSM_EXE", "")
    if not exe or not Path(exe).exists():
        pytest.skip("LDSM_EXE is not set to the ldsm tool (run through ctest)")
    return exe


@pytest.fixture(scope="session")
def scratch():
    root = Path(os.environ.get("LDSM_TEST_TMP", "/tmp")) / f"python_{os.getpid()}"
    shutil.rmtree(root, ignore_errors=True)
    root.mkdir(parents=True)
    yield root
    shutil.rmtree(root, ignore_errors=True)


@pytest.fixture(scope="session")
def scene(scratch):
    """The built-in `short` synthetic scene as a TUM-Mono folder."""
    out = scratch / "scene"
    subprocess.run([ldsm_exe(), "sim", "--scene", "short", "--out", str(out)], check=True,
                   capture_output=True)
    return out
