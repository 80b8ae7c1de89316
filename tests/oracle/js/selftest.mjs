#!/usr/bin/env node
// selftest.mjs — exercises skin_reference.mjs and validate_gltf.mjs (`npm test`).
//
// Runs both scripts on the sample models (if present) and on synthetic variants written to a
// temporary directory: .gltf + external .bin (+ external image), animation removed, skin removed,
// and a hand-built asset with a 2-primitive morph-target mesh instanced on two nodes and STEP /
// LINEAR / CUBICSPLINE channels.  skin_reference's built-in cross-check (three.js vs gltf_spec.mjs)
// is what validates the numbers; this script checks exit codes and a few invariants.
//
//   node selftest.mjs [MODEL_DIR]     (default MODEL_DIR: /work/shared/data/rigged)
//   SELFTEST_KEEP=1 keeps the temporary directory (printed at the end).

import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { readGltfFile } from './gltf_io.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const MODEL_DIR = process.argv[2] || '/work/shared/data/rigged';
const TMP = fs.mkdtempSync(path.join(os.tmpdir(), 'cgamesh-js-oracle-'));
let failures = 0;

function run(script, args) {
  const r = spawnSync(process.execPath, [path.join(HERE, script), ...args], { encoding: 'utf-8' });
  return { code: r.status, out: r.stdout, err: r.stderr };
}
function expect(cond, what) {
  process.stdout.write(`${cond ? 'ok  ' : 'FAIL'} ${what}\n`);
  if (!cond) failures++;
}
function skin(model, out, extra = []) {
  const r = run('skin_reference.mjs', [model, out, ...extra]);
  if (r.code !== 0) process.stdout.write(r.err);
  return { ...r, json: r.code === 0 ? JSON.parse(fs.readFileSync(out, 'utf-8')) : null };
}
function maxAbs(a, b) {
  let m = 0;
  for (let i = 0; i < a.length; i++) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
}

/** Writes json + bin as .gltf with an external .bin; images with bufferView become files. */
function writeGltf(json, bin, file) {
  const j = structuredClone(json);
  const base = path.basename(file, '.gltf');
  for (const [i, img] of (j.images || []).entries()) {
    if (img.bufferView === undefined) continue;
    const bv = j.bufferViews[img.bufferView];
    const ext = img.mimeType === 'image/jpeg' ? 'jpg' : 'png';
    const name = `${base}_img${i}.${ext}`;
    fs.writeFileSync(path.join(path.dirname(file), name), bin.subarray(bv.byteOffset || 0, (bv.byteOffset || 0) + bv.byteLength));
    delete img.bufferView;
    delete img.mimeType;
    img.uri = name;
  }
  fs.writeFileSync(path.join(path.dirname(file), `${base}.bin`), bin);
  j.buffers = [{ byteLength: bin.length, uri: `${base}.bin` }];
  fs.writeFileSync(file, JSON.stringify(j, null, 1));
}

// ---- a hand-built asset: morph targets, 2 primitives, 2 instances, STEP/LINEAR/CUBICSPLINE ----
function buildMorphAsset(file) {
  const chunks = [];
  let len = 0;
  const bufferViews = [];
  const accessors = [];
  const add = (arr, type, extra = {}) => {
    len = (len + 3) & ~3;
    const bytes = Buffer.from(arr.buffer, arr.byteOffset, arr.byteLength);
    chunks.push([len, bytes]);
    bufferViews.push({ buffer: 0, byteOffset: len, byteLength: bytes.length });
    len += bytes.length;
    const componentType = arr instanceof Float32Array ? 5126 : arr instanceof Uint16Array ? 5123 : 5125;
    const n = { SCALAR: 1, VEC3: 3, VEC4: 4 }[type];
    accessors.push({ bufferView: bufferViews.length - 1, componentType, count: arr.length / n, type, ...extra });
    return accessors.length - 1;
  };
  const minmax = (a, n) => {
    const mn = Array(n).fill(Infinity);
    const mx = Array(n).fill(-Infinity);
    for (let i = 0; i < a.length; i++) {
      mn[i % n] = Math.min(mn[i % n], a[i]);
      mx[i % n] = Math.max(mx[i % n], a[i]);
    }
    return { min: mn, max: mx };
  };
  const vec3 = (vals) => {
    const a = Float32Array.from(vals);
    return add(a, 'VEC3', minmax(a, 3));
  };
  const prim = (off) => {
    const pos = vec3([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0].map((v, i) => v + (i % 3 === 2 ? off : 0)));
    const t0 = vec3([0, 0, 0.5, 0, 0, 0, 0, 0, 0, 0.25, 0.25, 0.25]);
    const t1 = vec3([0, -0.5, 0, 0.5, 0, 0, 0, 0, 0, 0, 0, 1]);
    const idx = add(Uint16Array.from([0, 1, 2, 2, 1, 3]), 'SCALAR');
    return { attributes: { POSITION: pos }, indices: idx, targets: [{ POSITION: t0 }, { POSITION: t1 }] };
  };
  const p0 = prim(0);
  const p1 = prim(2);
  const tIn = (a) => add(Float32Array.from(a), 'SCALAR', { min: [Math.min(...a)], max: [Math.max(...a)] });
  const inStep = tIn([0, 0.5, 1.0]);
  const outWeights = add(Float32Array.from([0, 0, 1, 0.25, 0.5, 1]), 'SCALAR');
  const inLin = tIn([0, 1, 2]);
  const s = Math.SQRT1_2;
  const outRot = add(Float32Array.from([0, 0, 0, 1, 0, s, 0, s, 0.5, 0.5, 0.5, 0.5]), 'VEC4');
  const inCub = tIn([0.25, 1.25, 2.5]);
  // CUBICSPLINE layout per key: in-tangent, value, out-tangent
  const outTr = add(Float32Array.from([
    0, 0, 0, 0, 0, 0, 1, 2, 0,
    -1, 0.5, 0, 1, 1, 1, 2, -1, 0.5,
    0, 0, 1, 3, 0, -1, 0, 0, 0,
  ]), 'VEC3');
  const bin = Buffer.alloc((len + 3) & ~3);
  for (const [o, b] of chunks) b.copy(bin, o);
  const json = {
    asset: { version: '2.0', generator: 'cgamesh selftest' },
    scene: 0,
    scenes: [{ nodes: [0, 2] }],
    nodes: [
      { name: 'Root', children: [1], rotation: [0, 0, 0.3826834, 0.9238795], scale: [2, 2, 2] },
      { name: 'MorphA', mesh: 0, translation: [1, 0, 0] },
      { name: 'MorphB', mesh: 0, matrix: [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, -3, 1, 0, 1], weights: [0.5, 0.5] },
    ],
    meshes: [{ name: 'Quad', primitives: [p0, p1], weights: [0.1, 0.2] }],
    animations: [{
      name: 'mix',
      channels: [
        { sampler: 0, target: { node: 1, path: 'weights' } },
        { sampler: 1, target: { node: 0, path: 'rotation' } },
        { sampler: 2, target: { node: 1, path: 'translation' } },
      ],
      samplers: [
        { input: inStep, output: outWeights, interpolation: 'STEP' },
        { input: inLin, output: outRot, interpolation: 'LINEAR' },
        { input: inCub, output: outTr, interpolation: 'CUBICSPLINE' },
      ],
    }],
    accessors,
    bufferViews,
    buffers: [{ byteLength: bin.length }],
  };
  writeGltf(json, bin, file);
}

// ---- tests -----------------------------------------------------------------------------------
const models = ['RiggedSimple', 'RiggedFigure', 'CesiumMan'].map((m) => path.join(MODEL_DIR, `${m}.glb`)).filter((f) => fs.existsSync(f));
const TIMES = '0,0.25,0.6,1.0,1.5,2.5';
for (const model of models) {
  const name = path.basename(model, '.glb');
  const v = run('validate_gltf.mjs', [model, '--ignore', 'ACCESSOR_WEIGHTS_NON_NORMALIZED']);
  expect(v.code === 0, `validate ${name} (ignoring ACCESSOR_WEIGHTS_NON_NORMALIZED): exit ${v.code}`);
  for (const w of ['raw', 'normalized']) {
    for (const loop of ['clamp', 'repeat']) {
      const r = skin(model, path.join(TMP, `${name}.${w}.${loop}.json`), ['--times', TIMES, '--weights', w, '--loop', loop]);
      expect(r.code === 0, `skin_reference ${name} --weights ${w} --loop ${loop}: exit ${r.code}`);
    }
  }
  const ref = JSON.parse(fs.readFileSync(path.join(TMP, `${name}.raw.clamp.json`), 'utf-8'));
  const m0 = ref.meshes[0];
  expect(maxAbs(m0.posed['0'], m0.posed['1']) > 1e-3 * ref.bbox_diagonal, `${name}: pose at t=0 and t=1 differ`);
  expect(ref.meshes.every((m) => m.rest.length === 3 * m.vertex_count && Object.values(m.posed).every((p) => p.length === 3 * m.vertex_count)), `${name}: array lengths`);

  // .gltf + external .bin (+ external image): identical numbers, validator reads the externals
  const { json, bin } = readGltfFile(model);
  const gltfFile = path.join(TMP, `${name}.gltf`);
  writeGltf(json, bin, gltfFile);
  const vg = run('validate_gltf.mjs', [gltfFile, '--ignore', 'ACCESSOR_WEIGHTS_NON_NORMALIZED']);
  expect(vg.code === 0, `validate ${name}.gltf with external resources: exit ${vg.code}`);
  const rg = skin(gltfFile, path.join(TMP, `${name}.gltf.json`), ['--times', TIMES]);
  expect(rg.code === 0 && JSON.stringify(rg.json.meshes) === JSON.stringify(ref.meshes), `${name}.gltf gives the same output as the .glb`);

  // animation removed: posed == rest pose at every time
  const noAnim = structuredClone(json);
  delete noAnim.animations;
  writeGltf(noAnim, bin, path.join(TMP, `${name}_noanim.gltf`));
  const rn = skin(path.join(TMP, `${name}_noanim.gltf`), path.join(TMP, `${name}_noanim.json`), ['--times', '0,1']);
  expect(rn.code === 0 && rn.json.animation === null && maxAbs(rn.json.meshes[0].posed['0'], rn.json.meshes[0].posed['1']) === 0, `${name} without animation: static output`);

  // skin removed: the node's world transform applies
  const noSkin = structuredClone(json);
  for (const n of noSkin.nodes) delete n.skin;
  delete noSkin.skins;
  writeGltf(noSkin, bin, path.join(TMP, `${name}_noskin.gltf`));
  const rs = skin(path.join(TMP, `${name}_noskin.gltf`), path.join(TMP, `${name}_noskin.json`), ['--times', '0,1']);
  expect(rs.code === 0 && rs.json.meshes[0].skinned === false, `${name} without skin: non-skinned mesh, cross-check passes`);
}

// hand-built morph / interpolation asset
const morph = path.join(TMP, 'morph.gltf');
buildMorphAsset(morph);
const vm = run('validate_gltf.mjs', [morph]);
expect(vm.code === 0, `validate synthetic morph asset: exit ${vm.code}${vm.code ? '\n' + vm.out : ''}`);
for (const loop of ['clamp', 'repeat']) {
  const r = skin(morph, path.join(TMP, `morph.${loop}.json`), ['--times', '0,0.3,0.5,0.75,1,1.3,2,2.5,3.1', '--loop', loop]);
  expect(r.code === 0 && r.json.meshes.length === 4, `skin_reference on synthetic morph asset (--loop ${loop}): exit ${r.code}, ${r.json && r.json.meshes.length} meshes`);
  if (r.json) {
    const ids = r.json.meshes.map((m) => `${m.node}/${m.primitive}`).join(' ');
    expect(ids === 'MorphA/0 MorphA/1 MorphB/0 MorphB/1', `mesh order/mapping: ${ids}`);
  }
}

// broken inputs
const trunc = path.join(TMP, 'truncated.glb');
if (models.length) {
  fs.writeFileSync(trunc, fs.readFileSync(models[0]).subarray(0, 6000));
  const vt = run('validate_gltf.mjs', [trunc]);
  expect(vt.code === 1 && /error/.test(vt.out), `validate truncated GLB fails: exit ${vt.code}`);
  const st = run('skin_reference.mjs', [trunc, path.join(TMP, 't.json')]);
  expect(st.code === 1 && /truncated/.test(st.err), `skin_reference on truncated GLB fails: exit ${st.code}`);
}
expect(run('validate_gltf.mjs', [path.join(TMP, 'missing.glb')]).code === 2, 'validate missing file: exit 2');
expect(run('validate_gltf.mjs', []).code === 2, 'validate without args: exit 2');
expect(run('skin_reference.mjs', ['only-one-arg']).code === 2, 'skin_reference bad args: exit 2');
expect(run('skin_reference.mjs', ['a.glb', 'b.json', '--times', '0,nope']).code === 2, 'skin_reference bad --times: exit 2');

if (failures === 0 && !process.env.SELFTEST_KEEP) fs.rmSync(TMP, { recursive: true, force: true });
else process.stdout.write(`(kept ${TMP})\n`);
process.stdout.write(failures ? `${failures} FAILURE(S)\n` : 'all ok\n');
process.exit(failures ? 1 : 0);
