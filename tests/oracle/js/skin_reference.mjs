#!/usr/bin/env node
// skin_reference.mjs — three.js skinning oracle for cgamesh.
//
//   node skin_reference.mjs MODEL.(glb|gltf) OUT.json [--times 0,0.25,1.5] [--anim INDEX]
//                           [--loop clamp|repeat] [--weights raw|normalized]
//                           [--no-check] [--check-tol REL]
//
// Loads MODEL with three.js' GLTFLoader (images/textures stripped first, see README), poses it with
// AnimationMixer at each requested time and writes the glTF-spec world-space vertex positions of
// every mesh primitive in the default scene.  By default the result is cross-checked against an
// independent evaluator of the glTF spec (gltf_spec.mjs); exceeding the tolerance is an error.

import fs from 'node:fs';
import path from 'node:path';
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { readGltfFile, stripImages, packGlb, GltfIoError } from './gltf_io.mjs';
import { evaluatePose, primitiveWorldPositions, clipTime, animationDuration } from './gltf_spec.mjs';

const USAGE = `usage: node skin_reference.mjs MODEL.(glb|gltf) OUT.json [options]
  --times T0,T1,...   times in seconds (default: 0)
  --anim INDEX        animation index (default: 0; ignored if the asset has no animations)
  --loop clamp|repeat how times outside [0,duration] are mapped (default: clamp)
                      clamp  = THREE.LoopOnce + clampWhenFinished (t=duration -> last keyframe)
                      repeat = THREE.LoopRepeat, three's default (t=duration -> t=0)
  --weights raw|normalized
                      raw        = skin weights exactly as stored (glTF spec formula; default)
                      normalized = per-vertex weights divided by their sum, which is what
                                   three.js' GLTFLoader does on load (SkinnedMesh.normalizeSkinWeights)
  --no-check          skip the cross-check against the independent glTF-spec evaluator
  --check-tol REL     cross-check tolerance relative to the bbox diagonal (default: 1e-5)
OUT.json may be '-' for stdout.`;

function usage(msg) {
  if (msg) process.stderr.write(`skin_reference: ${msg}\n`);
  process.stderr.write(USAGE + '\n');
  process.exit(2);
}

/** Expected, user-facing failure: printed without a stack trace. */
class OracleError extends Error {}

function fail(msg) {
  process.stderr.write(`skin_reference: error: ${msg}\n`);
  process.exit(1);
}

function parseArgs(argv) {
  const opt = { times: [0], anim: null, loop: 'clamp', weights: 'raw', check: true, tol: 1e-5 };
  const pos = [];
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const val = () => {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      return argv[++i];
    };
    if (a === '--times') {
      const s = val();
      const ts = s.split(',').map((x) => x.trim());
      if (ts.length === 0 || ts.some((x) => x === '' || !Number.isFinite(Number(x)))) usage(`bad --times '${s}'`);
      opt.times = ts.map(Number);
    } else if (a === '--anim') {
      const s = val();
      if (!/^\d+$/.test(s)) usage(`bad --anim '${s}'`);
      opt.anim = Number(s);
    } else if (a === '--loop') {
      opt.loop = val();
      if (opt.loop !== 'clamp' && opt.loop !== 'repeat') usage(`bad --loop '${opt.loop}'`);
    } else if (a === '--weights') {
      opt.weights = val();
      if (opt.weights !== 'raw' && opt.weights !== 'normalized') usage(`bad --weights '${opt.weights}'`);
    } else if (a === '--no-check') {
      opt.check = false;
    } else if (a === '--check-tol') {
      const s = val();
      opt.tol = Number(s);
      if (!(opt.tol >= 0)) usage(`bad --check-tol '${s}'`);
    } else if (a === '-h' || a === '--help') {
      process.stdout.write(USAGE + '\n');
      process.exit(0);
    } else if (a.startsWith('--')) {
      usage(`unknown option ${a}`);
    } else {
      pos.push(a);
    }
  }
  if (pos.length !== 2) usage('expected MODEL and OUT');
  [opt.model, opt.out] = pos;
  const keys = opt.times.map(String);
  if (new Set(keys).size !== keys.length) usage('duplicate times');
  return opt;
}

function parseWithThree(arrayBuffer) {
  return new Promise((resolve, reject) => {
    new GLTFLoader().parse(arrayBuffer, '', resolve, (e) => reject(new OracleError(`three.js GLTFLoader: ${e && e.message ? e.message : e}`)));
  });
}

function maxAbsDiff(a, b) {
  let m = 0;
  for (let i = 0; i < a.length; i++) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
}

async function main() {
  const opt = parseArgs(process.argv.slice(2));
  const t0 = performance.now();

  // ---- load: our own reader (for the spec check) + three.js on an image-free GLB ------------
  const { json, bin } = readGltfFile(opt.model);
  if (opt.weights === 'raw') {
    // GLTFLoader unconditionally calls mesh.normalizeSkinWeights() on every SkinnedMesh "to fix
    // malformed assets"; the glTF formula uses the weights as stored, so disable that.
    THREE.SkinnedMesh.prototype.normalizeSkinWeights = function normalizeSkinWeightsDisabled() {};
  }
  const glb = packGlb(stripImages(json), bin);
  const gltf = await parseWithThree(glb);
  const tLoad = performance.now();
  if (!gltf.scene) throw new OracleError('asset has no scene');

  const nAnims = gltf.animations.length;
  let animIndex = opt.anim ?? 0;
  if (nAnims === 0) {
    if (opt.anim !== null) throw new OracleError(`--anim ${opt.anim}: asset has no animations`);
    animIndex = null;
  } else if (animIndex >= nAnims) {
    throw new OracleError(`--anim ${animIndex}: asset has only ${nAnims} animation(s)`);
  }
  const clip = animIndex === null ? null : gltf.animations[animIndex];

  // ---- collect meshes (three.js traversal order) ---------------------------------------------
  const assoc = gltf.parser.associations;
  const nodeObject = new Map(); // glTF node index -> three object
  gltf.scene.traverse((o) => {
    const a = assoc.get(o);
    if (a && a.nodes !== undefined) nodeObject.set(a.nodes, o);
  });
  const meshes = [];
  gltf.scene.traverse((o) => {
    if (o.isPoints || o.isLine) {
      process.stderr.write(`skin_reference: warning: skipping non-triangle primitive object '${o.name}'\n`);
      return;
    }
    if (!o.isMesh) return;
    if (o.isInstancedMesh) process.stderr.write(`skin_reference: warning: '${o.name}' is instanced; instancing ignored\n`);
    const a = assoc.get(o) || {};
    let nodeIndex = a.nodes;
    if (nodeIndex === undefined && o.parent) nodeIndex = (assoc.get(o.parent) || {}).nodes;
    const position = o.geometry.attributes.position;
    const rest = new Array(position.count * 3);
    const v = new THREE.Vector3();
    for (let i = 0; i < position.count; i++) {
      v.fromBufferAttribute(position, i);
      rest[3 * i] = v.x;
      rest[3 * i + 1] = v.y;
      rest[3 * i + 2] = v.z;
    }
    meshes.push({
      obj: o,
      entry: {
        name: o.name,
        node: nodeIndex !== undefined ? json.nodes[nodeIndex].name ?? null : null,
        node_index: nodeIndex ?? null,
        mesh: a.meshes ?? null,
        primitive: a.primitives ?? null,
        skinned: !!o.isSkinnedMesh,
        skin: nodeIndex !== undefined ? json.nodes[nodeIndex].skin ?? null : null,
        vertex_count: position.count,
        rest,
        posed: {},
      },
    });
  });

  // ---- pose at each time ---------------------------------------------------------------------
  const check = { max_abs_vs_spec: 0, max_abs_vs_spec_with_three_bones: 0, max_abs_skinned_without_matrixWorld: null, rest_max_abs: 0 };
  const duration = clip ? clip.duration : 0;
  const accCache = new Map();
  let bboxDiag = null;
  let tPoseTotal = 0;
  let tCheckTotal = 0;
  const v = new THREE.Vector3();
  for (const t of opt.times) {
    const key = String(t);
    const tp0 = performance.now();
    let mixer = null;
    if (clip) {
      mixer = new THREE.AnimationMixer(gltf.scene);
      const action = mixer.clipAction(clip);
      if (opt.loop === 'clamp') {
        action.setLoop(THREE.LoopOnce, 1);
        action.clampWhenFinished = true;
      }
      action.play();
      mixer.setTime(t);
    }
    gltf.scene.updateMatrixWorld(true);
    const raw = new Map();
    for (const { obj, entry } of meshes) {
      const n = entry.vertex_count;
      const out = new Array(3 * n);
      const local = entry.skinned ? new Float64Array(3 * n) : null;
      for (let i = 0; i < n; i++) {
        obj.getVertexPosition(i, v); // = fromBufferAttribute + morph targets + applyBoneTransform
        if (local) local.set([v.x, v.y, v.z], 3 * i);
        v.applyMatrix4(obj.matrixWorld);
        out[3 * i] = v.x;
        out[3 * i + 1] = v.y;
        out[3 * i + 2] = v.z;
      }
      entry.posed[key] = out;
      raw.set(entry, local);
    }
    tPoseTotal += performance.now() - tp0;

    if (bboxDiag === null) {
      const lo = [Infinity, Infinity, Infinity];
      const hi = [-Infinity, -Infinity, -Infinity];
      for (const { entry } of meshes) {
        const p = entry.posed[key];
        for (let i = 0; i < p.length; i++) {
          lo[i % 3] = Math.min(lo[i % 3], p[i]);
          hi[i % 3] = Math.max(hi[i % 3], p[i]);
        }
      }
      bboxDiag = meshes.length ? Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) : 0;
    }

    if (opt.check) {
      const tc0 = performance.now();
      const pose = evaluatePose(json, bin, animIndex, clip ? clipTime(t, duration, opt.loop) : 0);
      // Same spec formula, but with three.js' node world matrices (isolates the skinning convention).
      const threeWorld = pose.world.map((m, i) => (nodeObject.has(i) ? Float64Array.from(nodeObject.get(i).matrixWorld.elements) : m));
      const poseThreeBones = { world: threeWorld, weights: pose.weights };
      for (const { entry } of meshes) {
        if (entry.node_index === null || entry.primitive === null) throw new OracleError(`cannot map three.js mesh '${entry.name}' back to a glTF node/primitive`);
        const spec = primitiveWorldPositions(json, bin, entry.node_index, entry.primitive, pose, accCache, opt.weights === 'normalized');
        const spec3 = primitiveWorldPositions(json, bin, entry.node_index, entry.primitive, poseThreeBones, accCache, opt.weights === 'normalized');
        check.max_abs_vs_spec = Math.max(check.max_abs_vs_spec, maxAbsDiff(entry.posed[key], spec));
        check.max_abs_vs_spec_with_three_bones = Math.max(check.max_abs_vs_spec_with_three_bones, maxAbsDiff(entry.posed[key], spec3));
        if (entry.skinned) {
          check.max_abs_skinned_without_matrixWorld = Math.max(check.max_abs_skinned_without_matrixWorld ?? 0, maxAbsDiff(raw.get(entry), spec));
        }
        if (t === opt.times[0]) {
          const prim = json.meshes[json.nodes[entry.node_index].mesh].primitives[entry.primitive];
          check.rest_max_abs = Math.max(check.rest_max_abs, maxAbsDiff(entry.rest, accCache.get(prim.attributes.POSITION).data));
        }
      }
      tCheckTotal += performance.now() - tc0;
    }
    if (mixer) {
      mixer.stopAllAction();
      mixer.uncacheRoot(gltf.scene);
    }
  }

  const result = {
    generator: `three.js r${THREE.REVISION}`,
    model: path.basename(opt.model),
    animation: clip
      ? { index: animIndex, name: clip.name, duration: clip.duration, loop: opt.loop }
      : null,
    skin_weights: opt.weights,
    times: opt.times,
    meshes: meshes.map((m) => m.entry),
    bbox_diagonal: bboxDiag,
  };
  if (opt.check) {
    result.cross_check = { reference: 'gltf_spec.mjs (independent glTF 2.0 evaluator)', tolerance_rel: opt.tol, ...check };
  }
  const text = JSON.stringify(result);
  if (opt.out === '-') process.stdout.write(text + '\n');
  else fs.writeFileSync(opt.out, text + '\n');
  const tEnd = performance.now();

  const counts = meshes.map((m) => `${m.entry.name}:${m.entry.vertex_count}`).join(' ');
  let summary = `skin_reference: ${result.model}: ${meshes.length} mesh(es) [${counts}], ${opt.times.length} time(s), ` +
    `bbox_diagonal=${bboxDiag.toPrecision(6)}; load ${(tLoad - t0).toFixed(0)} ms, pose ${tPoseTotal.toFixed(0)} ms`;
  if (opt.check) {
    summary += `, check ${tCheckTotal.toFixed(0)} ms; max|three - spec|=${check.max_abs_vs_spec.toExponential(3)}` +
      ` (with three bones ${check.max_abs_vs_spec_with_three_bones.toExponential(3)}` +
      (check.max_abs_skinned_without_matrixWorld !== null
        ? `, skinned w/o mesh.matrixWorld ${check.max_abs_skinned_without_matrixWorld.toExponential(3)}`
        : '') +
      `, rest ${check.rest_max_abs.toExponential(3)})`;
  }
  process.stderr.write(`${summary}; total ${(tEnd - t0).toFixed(0)} ms\n`);

  if (opt.check) {
    const lim = opt.tol * Math.max(bboxDiag, 1e-12);
    if (!(check.max_abs_vs_spec <= lim) || !(check.max_abs_vs_spec_with_three_bones <= lim) || check.rest_max_abs !== 0) {
      fail(`three.js result disagrees with the glTF-spec evaluator beyond ${lim.toExponential(3)} (output written anyway; use --no-check to ignore)`);
    }
  }
}

main().catch((e) => {
  fail(e instanceof GltfIoError || e instanceof OracleError ? e.message : e && e.stack ? e.stack : String(e));
});
