#!/usr/bin/env bash
# The demo: the shipped CesiumMan animated in CGA. Poses it at a few times with each skinning
# mode (OBJ), converts it to glTF, and generates a new clip from keyframes. Results in out/.
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build/apps/cli/cgamesh}"
model=data/CesiumMan.glb
mkdir -p out

"$cli" info "$model"
for t in 0 0.5 1.0 1.5; do
  for mode in cga versor matrix dqs; do
    "$cli" pose "$model" --time "$t" --skinning "$mode" -o "out/cesium_t${t}_${mode}.obj"
  done
done
"$cli" pose "$model" --bind-pose -o out/cesium_bind.ply
"$cli" pose "$model" --time 0.5 --set "nodes[11]:rotate=0,1,0,40" \
  --set "nodes[19]:scale=1.6" --skinning versor -o out/cesium_edited.obj
"$cli" convert "$model" -o out/CesiumMan.glb
"$cli" animate "$model" -o out/cesium_wave.glb --blend log --fps 30 --name wave \
  --key "0:nodes[13]:rotate=1,0,0,0" \
  --key "1:nodes[13]:rotate=1,0,0,-70" \
  --key "2:nodes[13]:rotate=1,0,0,0"
echo "demo: wrote $(ls out | wc -l) files to out/"
ls -1 out
