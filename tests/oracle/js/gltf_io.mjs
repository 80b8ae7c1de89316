// gltf_io.mjs — minimal, dependency-free glTF 2.0 container I/O for the JS oracles.
//
//  * readGltfFile(path)        -> { json, bin }   (.glb or .gltf with external / data: buffers)
//  * stripImages(json)         -> removes images/textures/samplers and every texture reference
//  * packGlb(json, bin)        -> ArrayBuffer holding a single-buffer GLB
//
// The GLB re-packer exists so that three.js' GLTFLoader can be run in plain node (no DOM, no
// createImageBitmap): we hand it a GLB whose JSON chunk no longer mentions any image.

import fs from 'node:fs';
import path from 'node:path';

const GLB_MAGIC = 0x46546c67; // 'glTF'
const CHUNK_JSON = 0x4e4f534a; // 'JSON'
const CHUNK_BIN = 0x004e4942; // 'BIN\0'

export class GltfIoError extends Error {}

function parseGlb(buf, file) {
  if (buf.length < 12) throw new GltfIoError(`${file}: file too short for a GLB header (${buf.length} bytes)`);
  const magic = buf.readUInt32LE(0);
  const version = buf.readUInt32LE(4);
  const length = buf.readUInt32LE(8);
  if (magic !== GLB_MAGIC) throw new GltfIoError(`${file}: bad GLB magic 0x${magic.toString(16)}`);
  if (version !== 2) throw new GltfIoError(`${file}: unsupported GLB version ${version}`);
  if (length > buf.length) throw new GltfIoError(`${file}: GLB header says ${length} bytes but file has ${buf.length} (truncated?)`);
  let off = 12;
  let json = null;
  let bin = null;
  while (off < length) {
    if (off + 8 > length) throw new GltfIoError(`${file}: truncated chunk header at byte ${off}`);
    const clen = buf.readUInt32LE(off);
    const ctype = buf.readUInt32LE(off + 4);
    const start = off + 8;
    if (start + clen > length) throw new GltfIoError(`${file}: chunk at byte ${off} overruns the file (truncated?)`);
    const data = buf.subarray(start, start + clen);
    if (ctype === CHUNK_JSON && json === null) {
      try {
        json = JSON.parse(new TextDecoder('utf-8').decode(data));
      } catch (e) {
        throw new GltfIoError(`${file}: JSON chunk does not parse: ${e.message}`);
      }
    } else if (ctype === CHUNK_BIN && bin === null) {
      bin = data;
    }
    off = start + clen;
  }
  if (json === null) throw new GltfIoError(`${file}: no JSON chunk`);
  return { json, bin };
}

function decodeDataUri(uri) {
  const m = /^data:[^,]*?(;base64)?,(.*)$/s.exec(uri);
  if (!m) throw new GltfIoError(`unsupported data URI`);
  return m[1] ? Buffer.from(m[2], 'base64') : Buffer.from(decodeURIComponent(m[2]), 'latin1');
}

/**
 * Reads a .glb or .gltf file and returns { json, bin } where every buffer has been merged into
 * a single binary blob `bin` (a Buffer, possibly empty) referenced as buffer 0.
 */
export function readGltfFile(file) {
  let raw;
  try {
    raw = fs.readFileSync(file);
  } catch (e) {
    throw new GltfIoError(`cannot read ${file}: ${e.message}`);
  }
  let json;
  let glbBin = null;
  if (raw.length >= 4 && raw.readUInt32LE(0) === GLB_MAGIC) {
    ({ json, bin: glbBin } = parseGlb(raw, file));
  } else {
    try {
      json = JSON.parse(raw.toString('utf-8'));
    } catch (e) {
      throw new GltfIoError(`${file}: neither a GLB nor parseable glTF JSON: ${e.message}`);
    }
  }
  if (!json.asset || typeof json.asset.version !== 'string' || !json.asset.version.startsWith('2.')) {
    throw new GltfIoError(`${file}: not a glTF 2.x asset (asset.version=${json.asset && json.asset.version})`);
  }
  // Resolve all buffers and merge them into one, rewriting bufferViews.
  const buffers = json.buffers || [];
  const parts = [];
  const bases = [];
  let total = 0;
  buffers.forEach((b, i) => {
    let data;
    if (b.uri === undefined) {
      if (i !== 0 || glbBin === null) throw new GltfIoError(`${file}: buffer ${i} has no uri and there is no GLB BIN chunk`);
      data = glbBin;
    } else if (b.uri.startsWith('data:')) {
      data = decodeDataUri(b.uri);
    } else {
      const p = path.join(path.dirname(file), decodeURIComponent(b.uri));
      try {
        data = fs.readFileSync(p);
      } catch (e) {
        throw new GltfIoError(`${file}: cannot read buffer ${i} (${p}): ${e.message}`);
      }
    }
    if (data.length < b.byteLength) {
      throw new GltfIoError(`${file}: buffer ${i} has ${data.length} bytes, byteLength says ${b.byteLength} (truncated?)`);
    }
    total = (total + 7) & ~7; // keep every original buffer 8-byte aligned
    bases.push(total);
    parts.push([total, data.subarray(0, b.byteLength)]);
    total += b.byteLength;
  });
  const bin = Buffer.alloc((total + 3) & ~3);
  for (const [o, d] of parts) d.copy(bin, o);
  json = structuredClone(json);
  for (const bv of json.bufferViews || []) {
    bv.byteOffset = (bv.byteOffset || 0) + bases[bv.buffer];
    bv.buffer = 0;
  }
  json.buffers = total > 0 ? [{ byteLength: bin.length }] : [];
  if (total === 0 && (json.bufferViews || []).length > 0) {
    throw new GltfIoError(`${file}: bufferViews but no buffers`);
  }
  return { json, bin };
}

// Texture-only extensions that must go once textures are gone.
const TEXTURE_EXTENSIONS = new Set([
  'KHR_texture_basisu', 'EXT_texture_webp', 'EXT_texture_avif', 'KHR_texture_transform', 'MSFT_texture_dds',
]);

function stripTextureRefs(obj) {
  if (Array.isArray(obj)) {
    obj.forEach(stripTextureRefs);
    return;
  }
  if (obj === null || typeof obj !== 'object') return;
  for (const key of Object.keys(obj)) {
    const v = obj[key];
    // A textureInfo is an object with an integer `index`; every core/KHR property holding one
    // is named "...Texture" (baseColorTexture, normalTexture, clearcoatTexture, ...).
    if (/Texture$/.test(key) && v && typeof v === 'object' && Number.isInteger(v.index)) {
      delete obj[key];
    } else {
      stripTextureRefs(v);
    }
  }
}

/** Returns a deep copy of `json` with no images, textures, samplers or texture references. */
export function stripImages(json) {
  const j = structuredClone(json);
  delete j.images;
  delete j.textures;
  delete j.samplers;
  if (j.materials) stripTextureRefs(j.materials);
  for (const k of ['extensionsUsed', 'extensionsRequired']) {
    if (j[k]) {
      j[k] = j[k].filter((e) => !TEXTURE_EXTENSIONS.has(e));
      if (j[k].length === 0) delete j[k];
    }
  }
  return j;
}

/** Packs json + bin (buffer 0) into a GLB and returns it as an ArrayBuffer. */
export function packGlb(json, bin) {
  const jsonBytes = Buffer.from(JSON.stringify(json), 'utf-8');
  const jsonLen = (jsonBytes.length + 3) & ~3;
  const binLen = bin && bin.length ? (bin.length + 3) & ~3 : 0;
  const total = 12 + 8 + jsonLen + (binLen ? 8 + binLen : 0);
  const out = Buffer.alloc(total, 0);
  out.writeUInt32LE(GLB_MAGIC, 0);
  out.writeUInt32LE(2, 4);
  out.writeUInt32LE(total, 8);
  out.writeUInt32LE(jsonLen, 12);
  out.writeUInt32LE(CHUNK_JSON, 16);
  jsonBytes.copy(out, 20);
  out.fill(0x20, 20 + jsonBytes.length, 20 + jsonLen); // JSON chunk padded with spaces
  if (binLen) {
    const o = 20 + jsonLen;
    out.writeUInt32LE(binLen, o);
    out.writeUInt32LE(CHUNK_BIN, o + 4);
    bin.copy(out, o + 8);
  }
  return out.buffer.slice(out.byteOffset, out.byteOffset + out.length);
}
