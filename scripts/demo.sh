#!/usr/bin/env bash
# The demo: the shipped CesiumMan animated in CGA. Poses it at a few times with each skinning
# mode (OBJ), converts it to glTF, generates a new clip from keyframes, and cuts, tears and
# drills it. Results in out/.
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
# Surgery on the model posed at t = 0.5 s; every result keeps skin, skeleton and clip.
"$cli" cut "$model" --time 0.5 --plane 0,1,0,0.9 --cap -o out/cesium_upper.glb out/cesium_lower.glb
"$cli" tear "$model" --time 0.5 --open 0.01 -o out/cesium_torn.glb \
  --scalpel 0.01,0.90,2,0.01,0.90,0.06 \
  --scalpel -0.005,0.93,2,-0.005,0.93,0.06 \
  --scalpel -0.02,0.96,2,-0.02,0.96,0.06
"$cli" drill "$model" --time 0.5 --base 0.01,0.9,0.6 --tip 0.01,0.9,-0.6 --radius 0.04 --wall \
  -o out/cesium_drilled.glb
# Living tissue: the same tear in skin under tension (XPBD); the wound gapes, settles and is
# baked into a model that walks with it open.
"$cli" tear "$model" --time 0.5 --soft --tension 0.3 -o out/cesium_soft_torn.glb \
  --scalpel 0.01,0.90,2,0.01,0.90,0.06 \
  --scalpel -0.005,0.93,2,-0.005,0.93,0.06 \
  --scalpel -0.02,0.96,2,-0.02,0.96,0.06
echo "demo: wrote $(ls out | wc -l) files to out/"
ls -1 out
# Motor-handle deformation (paper sections III, IV, V, VI): spline bend, harmonic handles, FABRIK
# chain, a lattice twist by motors and by classic FFD, arms raised by a hand-made cage
# (data/cesiumman_cage.obj) with motors and classically.
for spec in cesiumman_bend cesiumman_handles cesiumman_ik ffd_twist_motor ffd_twist_classic cage_motor cage_classic; do
  "$cli" deform "$model" --spec data/specs/$spec.json -o out/$spec.obj
done
# ARAP with rotors (section VII) on the cow and the arm of tests/assets: the neck lifted, the arm bent.
"$cli" deform tests/assets/cow.obj --spec data/specs/arap_cow_bend.json -o out/arap_cow_bend.obj
"$cli" deform tests/assets/arm_16k.ply --spec data/specs/arap_arm_bend.json -o out/arap_arm_bend.ply
# The same bend written with its rig: the edited rest shape re-animates.
"$cli" deform "$model" --spec data/specs/cesiumman_bend.json -o out/cesiumman_bend.glb

# Pictures of the results (headless: EGL, no display or GPU needed). The man faces +x, so the
# `right` view sees his front. Re-posing edits follow the papers' figures: Kamarianakis &
# Papagiannakis Fig. 3D after the cut (elbow: rotation about (0,1,1) by 0.7 rad, translation,
# dilation 0.5; wrist: rotation by 0.3 rad) and Fig. 5B after the tear (elbow −1 rad and wrist
# +1 rad about y), coloured by the influence of the elbow, the joint most deformed.
elbow="nodes[14]" wrist="nodes[15]"
render=("$cli" render --size "${CGAMESH_PICTURE_SIZE:-960x720}")
"${render[@]}" "$model" --anim 0 --time 0.5 --view right -o out/cesium_posed.png
"${render[@]}" "$model" --anim 0 --time 0.5 --view right --color "joint:$elbow" --skeleton -o out/cesium_joint.png
"${render[@]}" out/cesium_upper.glb out/cesium_lower.glb --anim 0 --time 0.5 --view front --color piece -o out/cesium_cut.png
"${render[@]}" out/cesium_lower.glb --anim 0 --time 0.5 --camera 0.5,1.6,0.9,0,0.8,0,0,1,0 --frame --color new --wireframe \
  -o out/cesium_cut_cap.png
"${render[@]}" out/cesium_upper.glb out/cesium_lower.glb --anim 0 --time 0.5 --view front --color "joint:$elbow" \
  --set "$elbow:rotate=0,1,1,40.1" --set "$elbow:translate=0.1,0,0" --set "$elbow:scale=0.5" \
  --set "$wrist:rotate=0,1,1,17.2" -o out/cesium_cut_reposed.png
"${render[@]}" out/cesium_torn.glb --anim 0 --time 0.5 --camera 0.1,1.0,0.5,0.0,0.93,0.05,0,1,0 --fov 30 --color new \
  --wireframe -o out/cesium_torn.png
"${render[@]}" out/cesium_torn.glb --anim 0 --time 0.5 --view front --color "joint:$elbow" \
  --set "$elbow:rotate=0,1,0,-57.3" --set "$wrist:rotate=0,1,0,57.3" -o out/cesium_torn_reposed.png
"${render[@]}" out/cesium_drilled.glb --anim 0 --time 0.5 --camera 0.6,1.1,1.6,0.01,0.9,0,0,1,0 --frame \
  -o out/cesium_drilled.png
for spec in cesiumman_bend cesiumman_handles cesiumman_ik ffd_twist_motor ffd_twist_classic; do
  # The specs work in world space (the bind pose `info` boxes), where CesiumMan stands along +y.
  "${render[@]}" out/$spec.obj --camera 1,0.75,-0.4,0,0.75,0,0,1,0 --frame -o out/$spec.png
done
"${render[@]}" out/cesiumman_bend.glb --anim 0 --time 0.5 --view right -o out/cesiumman_bend_walking.png
"${render[@]}" out/arap_cow_bend.obj --view front -o out/arap_cow_bend.png
"${render[@]}" out/arap_arm_bend.ply --view front -o out/arap_arm_bend.png
# A moving picture: the soft-torn man walking through his clip (2 s, 48 frames), an animated WebP.
"$cli" render out/cesium_soft_torn.glb --time 0:2:48 --size "${CGAMESH_ANIMATION_SIZE:-480x480}" \
  --camera 0.6,1.05,1.2,0.0,0.9,0.0,0,1,0 --color new -o out/cesium_soft_tear.webp
echo "demo: pictures in out/*.png, an animation in out/cesium_soft_tear.webp"
