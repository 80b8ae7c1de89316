// gltf_spec.mjs — a small, independent (no three.js) evaluator of the glTF 2.0 specification,
// used to cross-check the three.js oracle.  Everything is computed in double precision
// straight from the glTF JSON + binary buffer:
//
//   * accessors (all component types, normalized ints, byteStride, matrix column padding, sparse)
//   * node local matrices (matrix or T*R*S) and world matrices of the whole node forest
//   * animation sampling: STEP / LINEAR (slerp for rotations) / CUBICSPLINE (spec Appendix C)
//   * morph targets (POSITION deltas, weights from mesh / node / animation)
//   * skinning (spec §3.7.3): world = Σ_sets Σ_k w_k · jointWorld[j_k] · inverseBind[j_k] · v,
//     the skinned mesh node's own transform being ignored; non-skinned: world = nodeWorld · v.
//     Optionally each vertex's weights are first divided by their sum (as three.js does on load).

const NCOMP = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16 };
const CTYPE = {
  5120: { size: 1, get: 'getInt8', norm: (c) => Math.max(c / 127, -1) },
  5121: { size: 1, get: 'getUint8', norm: (c) => c / 255 },
  5122: { size: 2, get: 'getInt16', norm: (c) => Math.max(c / 32767, -1) },
  5123: { size: 2, get: 'getUint16', norm: (c) => c / 65535 },
  5125: { size: 4, get: 'getUint32', norm: (c) => c / 4294967295 },
  5126: { size: 4, get: 'getFloat32', norm: (c) => c },
};

function readRaw(json, bin, bufferViewIndex, byteOffset, count, ncomp, componentType, normalized, type) {
  const ct = CTYPE[componentType];
  if (!ct) throw new Error(`unsupported componentType ${componentType}`);
  const out = new Float64Array(count * ncomp);
  if (bufferViewIndex === undefined) return out; // all zeros
  const bv = json.bufferViews[bufferViewIndex];
  const dv = new DataView(bin.buffer, bin.byteOffset, bin.byteLength);
  // Matrix columns are 4-byte aligned (spec §3.6.2.4): MAT2/MAT3 with 1- or 2-byte components.
  let rows = ncomp;
  let cols = 1;
  let colStride = 0;
  if (type === 'MAT2' || type === 'MAT3' || type === 'MAT4') {
    rows = type === 'MAT2' ? 2 : type === 'MAT3' ? 3 : 4;
    cols = rows;
    colStride = (rows * ct.size + 3) & ~3;
  }
  const elemSize = cols === 1 ? ncomp * ct.size : cols * colStride;
  const stride = bv.byteStride || elemSize;
  const base = (bv.byteOffset || 0) + (byteOffset || 0);
  for (let i = 0; i < count; i++) {
    for (let c = 0; c < cols; c++) {
      for (let r = 0; r < rows; r++) {
        const o = base + i * stride + c * colStride + r * ct.size;
        let v = dv[ct.get](o, true);
        if (normalized) v = ct.norm(v);
        out[i * ncomp + c * rows + r] = v;
      }
    }
  }
  return out;
}

/** Returns { count, ncomp, data: Float64Array } for accessor `index`. */
export function readAccessor(json, bin, index) {
  const a = json.accessors[index];
  const ncomp = NCOMP[a.type];
  const data = readRaw(json, bin, a.bufferView, a.byteOffset, a.count, ncomp, a.componentType, !!a.normalized, a.type);
  if (a.sparse) {
    const s = a.sparse;
    const idx = readRaw(json, bin, s.indices.bufferView, s.indices.byteOffset, s.count, 1, s.indices.componentType, false, 'SCALAR');
    const val = readRaw(json, bin, s.values.bufferView, s.values.byteOffset, s.count, ncomp, a.componentType, !!a.normalized, a.type);
    for (let k = 0; k < s.count; k++) {
      for (let c = 0; c < ncomp; c++) data[idx[k] * ncomp + c] = val[k * ncomp + c];
    }
  }
  return { count: a.count, ncomp, data };
}

// ---- 4x4 column-major matrices in Float64Array -------------------------------------------
export function identity() {
  const m = new Float64Array(16);
  m[0] = m[5] = m[10] = m[15] = 1;
  return m;
}
export function mul(a, b) {
  const o = new Float64Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
  }
  return o;
}
export function trs(t, q, s) {
  const [x, y, z, w] = q;
  const [sx, sy, sz] = s;
  const m = new Float64Array(16);
  m[0] = (1 - 2 * (y * y + z * z)) * sx;
  m[1] = 2 * (x * y + z * w) * sx;
  m[2] = 2 * (x * z - y * w) * sx;
  m[4] = 2 * (x * y - z * w) * sy;
  m[5] = (1 - 2 * (x * x + z * z)) * sy;
  m[6] = 2 * (y * z + x * w) * sy;
  m[8] = 2 * (x * z + y * w) * sz;
  m[9] = 2 * (y * z - x * w) * sz;
  m[10] = (1 - 2 * (x * x + y * y)) * sz;
  m[12] = t[0];
  m[13] = t[1];
  m[14] = t[2];
  m[15] = 1;
  return m;
}
export function xformPoint(m, x, y, z) {
  return [
    m[0] * x + m[4] * y + m[8] * z + m[12],
    m[1] * x + m[5] * y + m[9] * z + m[13],
    m[2] * x + m[6] * y + m[10] * z + m[14],
  ];
}

// ---- animation sampling (glTF 2.0 spec, Appendix C) ---------------------------------------
function slerp(a, b, t) {
  let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  let s = 1;
  if (d < 0) {
    d = -d;
    s = -1;
  }
  let ka;
  let kb;
  if (d > 1 - 1e-12) {
    ka = 1 - t;
    kb = t;
  } else {
    const ang = Math.acos(Math.min(d, 1));
    const sn = Math.sin(ang);
    ka = Math.sin((1 - t) * ang) / sn;
    kb = Math.sin(t * ang) / sn;
  }
  const r = [0, 1, 2, 3].map((i) => ka * a[i] + s * kb * b[i]);
  const n = Math.hypot(...r);
  return r.map((v) => v / n);
}

function normalizeQ(q) {
  const n = Math.hypot(...q);
  return q.map((v) => v / n);
}

/** Samples one animation sampler at time t; n = components per output element. */
export function sampleSampler(times, out, n, interpolation, t, isRotation) {
  const K = times.length;
  const cubic = interpolation === 'CUBICSPLINE';
  const value = (k) => {
    const o = cubic ? (3 * k + 1) * n : k * n;
    return Array.from(out.subarray(o, o + n));
  };
  if (K === 1 || t <= times[0]) return value(0);
  if (t >= times[K - 1]) return value(K - 1);
  let k = 0;
  while (k + 1 < K && times[k + 1] <= t) k++;
  const t0 = times[k];
  const t1 = times[k + 1];
  const td = t1 - t0;
  const u = (t - t0) / td;
  if (interpolation === 'STEP') return value(k);
  if (cubic) {
    const v0 = value(k);
    const b0 = Array.from(out.subarray((3 * k + 2) * n, (3 * k + 3) * n)); // out-tangent of k
    const v1 = value(k + 1);
    const a1 = Array.from(out.subarray((3 * (k + 1)) * n, (3 * (k + 1) + 1) * n)); // in-tangent of k+1
    const u2 = u * u;
    const u3 = u2 * u;
    const h00 = 2 * u3 - 3 * u2 + 1;
    const h10 = u3 - 2 * u2 + u;
    const h01 = -2 * u3 + 3 * u2;
    const h11 = u3 - u2;
    const r = v0.map((_, i) => h00 * v0[i] + td * h10 * b0[i] + h01 * v1[i] + td * h11 * a1[i]);
    return isRotation ? normalizeQ(r) : r;
  }
  const a = value(k);
  const b = value(k + 1);
  if (isRotation) return slerp(a, b, u);
  return a.map((v, i) => v + u * (b[i] - v));
}

/** Duration as three.js computes it: the largest keyframe time over all channels. */
export function animationDuration(json, bin, animIndex) {
  const anim = json.animations[animIndex];
  let d = 0;
  for (const ch of anim.channels) {
    const s = anim.samplers[ch.sampler];
    const times = readAccessor(json, bin, s.input).data;
    d = Math.max(d, times[times.length - 1]);
  }
  return d;
}

/** Maps a requested time to clip time: 'clamp' -> [0,duration], 'repeat' -> t mod duration. */
export function clipTime(t, duration, loop) {
  if (!(duration > 0)) return 0;
  if (loop === 'repeat') return t - duration * Math.floor(t / duration);
  return Math.min(Math.max(t, 0), duration);
}

/**
 * Evaluates the whole asset at clip time tc (or rest pose if animIndex is null).
 * Returns { world: Float64Array[] per node, weights: number[][] per node (morph weights) }.
 */
export function evaluatePose(json, bin, animIndex, tc) {
  const nodes = json.nodes || [];
  const local = nodes.map((nd) => ({
    matrix: nd.matrix ? Float64Array.from(nd.matrix) : null,
    t: nd.translation ? [...nd.translation] : [0, 0, 0],
    r: nd.rotation ? [...nd.rotation] : [0, 0, 0, 1],
    s: nd.scale ? [...nd.scale] : [1, 1, 1],
    w: nd.weights ? [...nd.weights] : nd.mesh !== undefined && json.meshes[nd.mesh].weights ? [...json.meshes[nd.mesh].weights] : null,
  }));
  if (animIndex !== null && animIndex !== undefined) {
    const anim = json.animations[animIndex];
    for (const ch of anim.channels) {
      if (ch.target.node === undefined) continue;
      const s = anim.samplers[ch.sampler];
      const times = readAccessor(json, bin, s.input).data;
      const out = readAccessor(json, bin, s.output).data;
      const path = ch.target.path;
      const L = local[ch.target.node];
      const n = path === 'rotation' ? 4 : path === 'weights' ? out.length / times.length / (s.interpolation === 'CUBICSPLINE' ? 3 : 1) : 3;
      const v = sampleSampler(times, out, n, s.interpolation || 'LINEAR', tc, path === 'rotation');
      if (path === 'translation') L.t = v;
      else if (path === 'rotation') L.r = v;
      else if (path === 'scale') L.s = v;
      else if (path === 'weights') L.w = v;
    }
  }
  const parent = new Array(nodes.length).fill(-1);
  nodes.forEach((nd, i) => (nd.children || []).forEach((c) => (parent[c] = i)));
  const world = new Array(nodes.length).fill(null);
  const getWorld = (i) => {
    if (world[i]) return world[i];
    const L = local[i];
    const m = L.matrix ? L.matrix : trs(L.t, L.r, L.s);
    world[i] = parent[i] < 0 ? m : mul(getWorld(parent[i]), m);
    return world[i];
  };
  nodes.forEach((_, i) => getWorld(i));
  return { world, weights: local.map((L) => L.w) };
}

/**
 * World-space positions of primitive `primIndex` of the mesh on node `nodeIndex` for a pose from
 * evaluatePose().  Returns a Float64Array [x,y,z,...] in POSITION accessor order.
 */
export function primitiveWorldPositions(json, bin, nodeIndex, primIndex, pose, cache = new Map(), normalizeWeights = false) {
  const acc = (i) => {
    if (!cache.has(i)) cache.set(i, readAccessor(json, bin, i));
    return cache.get(i);
  };
  const node = json.nodes[nodeIndex];
  const prim = json.meshes[node.mesh].primitives[primIndex];
  const pos = acc(prim.attributes.POSITION);
  const n = pos.count;
  const p = Float64Array.from(pos.data);
  // morph targets
  const w = pose.weights[nodeIndex];
  if (prim.targets && w) {
    prim.targets.forEach((tg, k) => {
      if (tg.POSITION === undefined || !w[k]) return;
      const d = acc(tg.POSITION).data;
      for (let i = 0; i < 3 * n; i++) p[i] += w[k] * d[i];
    });
  }
  const out = new Float64Array(3 * n);
  if (node.skin === undefined) {
    const M = pose.world[nodeIndex];
    for (let i = 0; i < n; i++) out.set(xformPoint(M, p[3 * i], p[3 * i + 1], p[3 * i + 2]), 3 * i);
    return out;
  }
  const skin = json.skins[node.skin];
  const ibm = skin.inverseBindMatrices !== undefined ? acc(skin.inverseBindMatrices).data : null;
  const jointMats = skin.joints.map((j, k) => {
    const inv = ibm ? ibm.subarray(16 * k, 16 * k + 16) : identity();
    return mul(pose.world[j], inv);
  });
  const sets = [];
  for (let s = 0; prim.attributes[`JOINTS_${s}`] !== undefined; s++) {
    sets.push([acc(prim.attributes[`JOINTS_${s}`]).data, acc(prim.attributes[`WEIGHTS_${s}`]).data]);
  }
  for (let i = 0; i < n; i++) {
    let x = 0;
    let y = 0;
    let z = 0;
    let scale = 1;
    if (normalizeWeights) {
      let sum = 0;
      for (const [, W] of sets) for (let c = 0; c < 4; c++) sum += Math.abs(W[4 * i + c]);
      scale = sum > 0 ? 1 / sum : 1;
    }
    for (const [J, W] of sets) {
      for (let c = 0; c < 4; c++) {
        const wt = W[4 * i + c] * scale;
        if (wt === 0) continue;
        const m = jointMats[J[4 * i + c]];
        const v = xformPoint(m, p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        x += wt * v[0];
        y += wt * v[1];
        z += wt * v[2];
      }
    }
    out[3 * i] = x;
    out[3 * i + 1] = y;
    out[3 * i + 2] = z;
  }
  return out;
}
