#!/usr/bin/env bash
# `pip install .` into a fresh virtual environment (with the system's site packages: Debian's
# numpy), offline, reusing the CMake build in $CGAMESH_BUILD_DIR; then imports the installed
# package from outside the source tree and checks that it works.
# Usage: pip_install_test.sh PYTHON SOURCE_DIR WORK_DIR
set -euo pipefail
python="$1" source="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
"$python" -m venv --system-site-packages "$work/venv"
# The README's command, offline: no index (numpy comes from the system site packages), no build
# isolation (Debian's setuptools and wheel are used).
PIP_NO_INDEX=1 "$work/venv/bin/python" -m pip install --no-build-isolation --quiet "$source"
cd "$work"
"$work/venv/bin/python" - "$source" <<'PY'
import pathlib
import sys

import cgamesh
from cgamesh import cga

source = pathlib.Path(sys.argv[1])
assert "venv" in cgamesh.__file__, cgamesh.__file__
model = cgamesh.load(str(source / "data" / "CesiumMan.glb"))
assert model.skin()[0].shape == model.meshes[0].positions.shape
assert abs(cga.down(cga.up([1, 2, 3]))[2] - 3) < 1e-12
print("pip install: cgamesh", cgamesh.__version__, "from", cgamesh.__file__)
PY
