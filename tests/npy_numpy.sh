#!/bin/bash
# NumPy reads every .npy file hsr render writes (depth, ids, normals), with the dtype, shape and
# values docs/formats.md gives. Usage: npy_numpy.sh HSR PYTHON MODELS_DIR SCRATCH_DIR.
# Exits 77 (skipped) when PYTHON has no numpy.
set -euo pipefail
hsr=$1 python=$2 models=$3 scratch=$4

if ! "$python" -c 'import numpy' 2>/dev/null; then
    echo "skipped: $python cannot import numpy (Debian: apt-get install python3-numpy; or -DHSR_PYTHON=...)"
    exit 77
fi
rm -rf "$scratch" && mkdir -p "$scratch"
"$hsr" render "$models/cube.obj" --eye 0,0,10 --target 0,0,0 --width 40 --height 30 -o "$scratch/cube.png" \
    --depth-out "$scratch/depth.npy" --id-out "$scratch/ids.npy" --normal-out "$scratch/normals.npy"

"$python" - "$scratch" <<'PY'
import sys
import numpy as np

folder = sys.argv[1]
depth = np.load(f"{folder}/depth.npy")
ids = np.load(f"{folder}/ids.npy")
normals = np.load(f"{folder}/normals.npy")
assert depth.dtype == np.dtype("<f4") and depth.shape == (30, 40), (depth.dtype, depth.shape)
assert ids.dtype == np.dtype("<i4") and ids.shape == (30, 40, 3), (ids.dtype, ids.shape)
assert normals.dtype == np.dtype("<f4") and normals.shape == (30, 40, 3), (normals.dtype, normals.shape)
covered = ids[:, :, 0] >= 0
assert covered.any() and (~covered).any()
# The cube's front face, z = 1, seen from z = 10 along -z: 9 away, facing the eye.
assert np.allclose(depth[covered], 9.0, rtol=1e-4), depth[covered].min()
assert np.isposinf(depth[~covered]).all()
assert np.allclose(normals[covered], [0, 0, 1], atol=1e-6)
assert (normals[~covered] == 0).all()
assert (ids[~covered] == -1).all() and (ids[covered][:, 2] == 0).all()
print("numpy read depth.npy, ids.npy and normals.npy")
PY
