#!/usr/bin/env bash
# Regenerates the README's pictures in docs/: runs the demo with pictures of 480×360 (the
# animation 360×360) and keeps a few of them. Usage: scripts/pictures.sh [path/to/cgamesh] (after `make build`).
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build/apps/cli/cgamesh}"
CGAMESH_PICTURE_SIZE=480x360 CGAMESH_ANIMATION_SIZE=360x360 bash scripts/demo.sh "$cli" > /dev/null
mkdir -p docs
for name in cesium_posed cesium_cut_cap cesium_cut_reposed cesium_torn cesium_drilled cesiumman_bend; do
  cp "out/$name.png" "docs/$name.png"
done
cp out/cesium_soft_tear.webp docs/cesium_soft_tear.webp
echo "pictures: docs/*.png and docs/cesium_soft_tear.webp regenerated"
