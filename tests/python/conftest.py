"""Shared set-up of the Python module's tests (docs/python.md).

CTest runs them with PYTHONPATH at the build tree's package and the tools in
AAL_TEST_BIN_DIR (tests/python/CMakeLists.txt); by hand:

    PYTHONPATH=build/python AAL_TEST_BIN_DIR=build/bin /usr/bin/python3 -m pytest tests/python
"""

import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(
    os.environ.get("AAL_TEST_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN_DIR = pathlib.Path(os.environ.get("AAL_TEST_BIN_DIR", SOURCE_DIR / "build" / "bin"))
JACKSBORO = SOURCE_DIR / "heightmaps" / "jacksboro_fault_dem.tif"


def run_tool(name, *args, env=None):
    """Runs a tool of the build; fails the test with its stderr unless it exits 0."""
    tool = BIN_DIR / name
    if not tool.exists():
        pytest.fail(f"{tool} is not built (AAL_TEST_BIN_DIR={BIN_DIR})")
    result = subprocess.run([str(tool), *map(str, args)], capture_output=True, text=True,
                            env=env, timeout=120)
    assert result.returncode == 0, f"{name} {args} exited {result.returncode}:\n{result.stderr}"
    return result


@pytest.fixture
def tool_env(tmp_path):
    """The tools' environment with their aperture-map cache in the test's folder."""
    env = dict(os.environ)
    env["AAL_CACHE_DIR"] = str(tmp_path / "cache")
    return env


@pytest.fixture(scope="session")
def jacksboro():
    """The shipped DEM as aperture.rio reads it: (heights, RasterInfo)."""
    from aperture import rio
    return rio.read(JACKSBORO)


def hills(height=96, width=128, seed=7):
    """A small deterministic terrain with relief at several scales (metres)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    z = 40 * np.sin(x / 9.0) * np.cos(y / 13.0) + 25 * np.cos((x + 2 * y) / 21.0)
    return (z + 3 * rng.standard_normal((height, width)) + 300).astype(np.float32)
