"""What the tests of the Python package share: where hsr and the models are (set by CTest, see
python/CMakeLists.txt), the hsr executable run as a command, and a PNG reader that is not hsr's, so
that pictures are compared pixel by pixel without trusting hsr's own encoder."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tests" / "tools"))
from same_pictures import png_pixels  # noqa: E402

HSR = os.environ.get("HSR_EXECUTABLE", "")
MODELS = pathlib.Path(os.environ.get("HSR_MODELS", pathlib.Path(__file__).resolve().parents[2] / "models"))


@pytest.fixture(scope="session")
def models():
    if not (MODELS / "bunny.obj").is_file():
        pytest.skip(f"no models in {MODELS} (bash models/fetch-models.sh)")
    return MODELS


@pytest.fixture(scope="session")
def hsr_cli():
    if not HSR or not os.access(HSR, os.X_OK):
        pytest.skip("HSR_EXECUTABLE does not name the hsr executable")

    def run(*args, check=True):
        result = subprocess.run([HSR, *map(str, args)], capture_output=True, text=True)
        if check and result.returncode != 0:
            raise AssertionError(f"hsr {' '.join(map(str, args))} failed: {result.stderr}")
        return result

    return run


def read_png(path):
    """The pixels of an 8-bit greyscale, RGB or RGBA PNG as an (H, W, C) array, decoded by
    tests/tools/same_pictures.py rather than by hsr."""
    width, height, depth, colour, rows = png_pixels(path)
    assert depth == 8, f"{path}: {depth}-bit samples"
    channels = {0: 1, 2: 3, 6: 4}[colour]
    return np.frombuffer(rows, dtype=np.uint8).reshape(height, width, channels)
