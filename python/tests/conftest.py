"""What the tests of the Python package share: where hsr and the models are (set by CTest, see
python/CMakeLists.txt), the hsr executable run as a command, and a PNG reader of their own, so that
pictures are compared pixel by pixel without trusting hsr's own encoder."""

import os
import pathlib
import struct
import subprocess
import zlib

import numpy as np
import pytest

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
    """The pixels of an 8-bit, non-interlaced greyscale, RGB or RGBA PNG, as an (H, W, C) array."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG file"
    at, idat, header = 8, b"", None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    width, height, depth, color_type, _, _, interlace = header
    assert depth == 8 and interlace == 0, "only 8-bit non-interlaced PNGs are read here"
    channels = {0: 1, 2: 3, 6: 4}[color_type]
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(height, 1 + width * channels)
    rows = np.zeros((height, width * channels), dtype=np.int32)
    for y in range(height):
        kind, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        above = rows[y - 1] if y > 0 else np.zeros_like(line)
        row = np.zeros_like(line)
        for x in range(len(line)):
            left = row[x - channels] if x >= channels else 0
            up_left = above[x - channels] if x >= channels else 0
            if kind == 0:
                predicted = 0
            elif kind == 1:
                predicted = left
            elif kind == 2:
                predicted = above[x]
            elif kind == 3:
                predicted = (left + above[x]) // 2
            else:
                p = left + above[x] - up_left
                pa, pb, pc = abs(p - left), abs(p - above[x]), abs(p - up_left)
                predicted = left if pa <= pb and pa <= pc else above[x] if pb <= pc else up_left
            row[x] = (line[x] + predicted) & 0xFF
        rows[y] = row
    return rows.astype(np.uint8).reshape(height, width, channels)
