#!/usr/bin/env node
// gen_table.js -- reference-table generator for cgamesh's C++ tests.
//
// Uses ganja.js (an independent Geometric Algebra implementation) to compute
// products and unary operations of random multivectors in CGA G(4,1), and
// writes them, mapped into cgamesh's blade order, as JSON.
//
// Usage: node gen_table.js OUT.json
//
// The output is deterministic (fixed-seed PRNG written below); running the
// script twice must produce byte-identical files.
//
// cgamesh conventions (see README.md):
//   basis vectors e1,e2,e3 (+1), e+ (+1), e- (-1)
//   blade index = bitmask: bit0=e1, bit1=e2, bit2=e3, bit3=e+, bit4=e-
//   blade i = product of its basis vectors in increasing bit order.
//   ganja Algebra(4,1): e1..e4 square to +1, e5 to -1, so our bit k <-> ganja e(k+1).

'use strict';

const fs = require('fs');
const Algebra = require('ganja.js');
const GANJA_VERSION = require('ganja.js/package.json').version;

// ---------------------------------------------------------------- parameters
const SEED = 0xC6A3E5; // arbitrary fixed seed
const N_CASES = 1200;
const N_VERSOR_CASES = 200;
const INV_TOL = 1e-9;    // max |a*inv-1|, |inv*a-1| (inf-norm) to accept ganja's inverse
const EXP_TOL = 1e-11;   // max deviation of ganja's Exp from an independent series exp, relative
const ORDER = 'bitmask e1=1,e2=2,e3=4,e+=8,e-=16';

if (process.argv.length < 3) {
  process.stderr.write('usage: node gen_table.js OUT.json\n');
  process.exit(2);
}
const OUT = process.argv[2];

// ---------------------------------------------------------------- PRNG
// mulberry32, fixed seed. Returns doubles in [0,1) with 32 random bits.
function mulberry32(seed) {
  let s = seed >>> 0;
  return function () {
    s = (s + 0x6D2B79F5) >>> 0;
    let t = s;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
const rand = mulberry32(SEED);
const uniform = () => 2 * rand() - 1; // [-1, 1), exactly representable

// ---------------------------------------------------------------- helpers
function fail(msg) {
  process.stderr.write('gen_table.js: SELF-CHECK FAILED: ' + msg + '\n');
  process.exit(1);
}
const NB = 32;
const popcount = (x) => { let c = 0; while (x) { c += x & 1; x >>>= 1; } return c; };
const grade = popcount;
const BIT_NAMES = ['1', '2', '3', '+', '-'];
const bladeName = (i) => {
  if (i === 0) return '1';
  let s = 'e';
  for (let k = 0; k < 5; ++k) if (i & (1 << k)) s += BIT_NAMES[k];
  return s;
};
const ourBasis = (i, c = 1) => { const v = new Array(NB).fill(0); v[i] = c; return v; };
const maxAbsDiff = (x, y) => { let m = 0; for (let i = 0; i < NB; ++i) m = Math.max(m, Math.abs(x[i] - y[i])); return m; };
const maxAbs = (x) => { let m = 0; for (let i = 0; i < NB; ++i) m = Math.max(m, Math.abs(x[i])); return m; };
const exactlyEqual = (x, y) => { for (let i = 0; i < NB; ++i) if (x[i] !== y[i]) return false; return true; };
const scaled = (x, s) => x.map((c) => c * s);

// Independent reference for products of OUR basis blades (bitmask algorithm):
// sign from reordering into increasing bit order, times the metric of the
// cancelled vectors (only e-, bit4, squares to -1).
function ourBladeProduct(i, j) {
  let swaps = 0;
  for (let a = i >> 1; a; a >>= 1) swaps += popcount(a & j);
  let sign = (swaps & 1) ? -1 : 1;
  if (i & j & 16) sign = -sign;
  return [sign, i ^ j];
}

// ---------------------------------------------------------------- the algebra
// NOTE: ganja's default element storage is Float32Array -- we need Float64Array.
const A = Algebra({ p: 4, q: 1, baseType: Float64Array });
const GBASIS = A.describe().basis; // flat list of ganja basis names
if (GBASIS.length !== NB) fail('ganja basis has ' + GBASIS.length + ' elements');
{
  const x = A.Coeff(1, 0.1).Mul(A.Coeff(1, 0.3));
  if (x[0] !== 0.1 * 0.3) fail('ganja is not computing in double precision');
}

// ganja basis vector for our bit k is ganja e(k+1)
const gVec = (k) => {
  const idx = GBASIS.indexOf('e' + (k + 1));
  if (idx < 0) fail('ganja has no basis vector e' + (k + 1));
  return A.Coeff(idx, 1);
};
{ // metric check of the basis vectors
  const expect = [1, 1, 1, 1, -1];
  for (let k = 0; k < 5; ++k) {
    const sq = gVec(k).Mul(gVec(k));
    if (!Array.from(sq).every((c, g) => c === (g === 0 ? expect[k] : 0)))
      fail('ganja e' + (k + 1) + '^2 != ' + expect[k]);
  }
}

// Build mapping: our blade i == G_SIGN[i] * ganja basis element G_IDX[i],
// by computing the product of ganja basis vectors in increasing bit order.
const G_IDX = new Array(NB), G_SIGN = new Array(NB);
for (let i = 0; i < NB; ++i) {
  let prod = A.Scalar(1);
  for (let k = 0; k < 5; ++k) if (i & (1 << k)) prod = prod.Mul(gVec(k));
  const nz = [];
  for (let g = 0; g < NB; ++g) if (prod[g] !== 0) nz.push(g);
  if (nz.length !== 1 || Math.abs(prod[nz[0]]) !== 1) fail('blade ' + bladeName(i) + ' is not a unit ganja blade');
  G_IDX[i] = nz[0];
  G_SIGN[i] = prod[nz[0]];
}
if (new Set(G_IDX).size !== NB) fail('blade mapping is not a bijection');

function toGanja(arr) {
  const g = new A();
  for (let i = 0; i < NB; ++i) g[G_IDX[i]] = G_SIGN[i] * arr[i];
  return g;
}
function fromGanja(g) {
  const arr = new Array(NB);
  for (let i = 0; i < NB; ++i) {
    const v = G_SIGN[i] * g[G_IDX[i]];
    if (!Number.isFinite(v)) fail('non-finite ganja result');
    arr[i] = v === 0 ? 0 : v; // normalise -0
  }
  return arr;
}
const E = (i, c = 1) => toGanja(ourBasis(i, c));
const I_G = E(31); // our pseudoscalar I = e1 e2 e3 e+ e-, as a ganja element

// ---------------------------------------------------------------- self-checks
// 1. Full Cayley table of our blades vs the independent bitmask rule.
for (let i = 0; i < NB; ++i) for (let j = 0; j < NB; ++j) {
  const [s, k] = ourBladeProduct(i, j);
  if (!exactlyEqual(fromGanja(E(i).Mul(E(j))), ourBasis(k, s)))
    fail('Cayley table mismatch at ' + bladeName(i) + '*' + bladeName(j));
}
// 2. A few products checked by hand.
{
  const hand = [
    [1, 2, 1, 3],      // e1 e2 = +e12
    [2, 1, -1, 3],     // e2 e1 = -e12
    [8, 8, 1, 0],      // e+ e+ = +1
    [16, 16, -1, 0],   // e- e- = -1
    [24, 24, 1, 0],    // (e+e-)^2 = +1
    [16, 8, -1, 24],   // e- e+ = -e+-
    [5, 2, -1, 7],     // (e1e3) e2 = -e123
    [31, 31, -1, 0],   // I^2 = -1
    [3, 31, -1, 28],   // e12 I = e1e2e1e2e3e+e- = -e3+-
    [6, 5, 1, 3],      // e23 e13 = e2 e3 e1 e3 = -e2 e1 e3 e3 = -e2 e1 = +e12
  ];
  for (const [i, j, s, k] of hand)
    if (!exactlyEqual(fromGanja(E(i).Mul(E(j))), ourBasis(k, s)))
      fail('hand check ' + bladeName(i) + '*' + bladeName(j) + ' != ' + s + '*' + bladeName(k));
}
// 3. Verify what ganja's operators do, on all basis blades.
const notes = {};
{
  let wedgeOK = true, ldotOK = true, fatDotOK = true, hestenesOK = true;
  for (let i = 0; i < NB; ++i) for (let j = 0; j < NB; ++j) {
    const [s, k] = ourBladeProduct(i, j);
    const gp = ourBasis(k, s), zero = ourBasis(0, 0);
    const gi = grade(i), gj = grade(j), gk = grade(k);
    const w = fromGanja(E(i).Wedge(E(j)));
    const lc = fromGanja(E(i).LDot(E(j)));
    const dt = fromGanja(E(i).Dot(E(j)));
    if (!exactlyEqual(w, gk === gi + gj ? gp : zero)) wedgeOK = false;
    if (!exactlyEqual(lc, gk === gj - gi ? gp : zero)) ldotOK = false;           // left contraction
    if (!exactlyEqual(dt, gk === Math.abs(gj - gi) ? gp : zero)) fatDotOK = false; // "fat dot"
    if (!exactlyEqual(dt, (gi && gj && gk === Math.abs(gj - gi)) ? gp : zero)) hestenesOK = false;
  }
  if (!wedgeOK) fail('ganja Wedge is not the outer product <A_r B_s>_{r+s}');
  if (!ldotOK) fail('ganja LDot is not the left contraction <A_r B_s>_{s-r}');
  if (!fatDotOK) fail('ganja Dot is not the fat dot <A_r B_s>_{|s-r|}');
  if (hestenesOK) fail('ganja Dot unexpectedly equals the Hestenes inner product');
  notes.op = 'ganja a.Wedge(b): sum over grades <a_r b_s>_{r+s}';
  notes.lc = 'ganja a.LDot(b) (inline operator <<): left contraction, sum over grades <a_r b_s>_{s-r} (zero if r>s); scalars: 1 lc B = B, A_r lc 1 = 0 for r>0';
  notes.dot = 'ganja a.Dot(b) (inline operator |): "fat dot" symmetric inner product, sum over grades <a_r b_s>_{|s-r|}, scalars INCLUDED (1.B = B, A.1 = A); NOT the Hestenes inner product (which drops scalar terms)';

  // unary involutions: compare against the textbook sign patterns
  const textbook = {
    reverse: (g) => ((g * (g - 1) / 2) % 2 ? -1 : 1),       // flips grades 2,3
    involution: (g) => (g % 2 ? -1 : 1),                      // flips grades 1,3,5
    clifford_conjugate: (g) => ((g * (g + 1) / 2) % 2 ? -1 : 1), // flips grades 1,2,5
  };
  const which = (op) => Object.keys(textbook).filter((name) =>
    [...Array(NB).keys()].every((i) => exactlyEqual(fromGanja(op(E(i))), ourBasis(i, textbook[name](grade(i))))));
  const rv = which((x) => x.Reverse), iv = which((x) => x.Involute), cj = which((x) => x.Conjugate);
  if (rv.join() !== 'reverse') fail('ganja .Reverse is ' + rv);
  if (iv.join() !== 'involution') fail('ganja .Involute is ' + iv);
  if (cj.join() !== 'clifford_conjugate') fail('ganja .Conjugate is ' + cj);
  notes.rev = 'ganja a.Reverse: reverse, flips sign of grades 2,3';
  notes.inv_grade = 'ganja a.Involute: grade involution, flips sign of grades 1,3,5';
  notes.conj = 'ganja a.Conjugate (inline operator ~): Clifford conjugate, flips sign of grades 1,2,5';

  // ganja's .Dual vs ours (-a I)
  let dualIsAI = true, dualIsMinusAI = true;
  for (let i = 0; i < NB; ++i) {
    const d = fromGanja(E(i).Dual), aI = fromGanja(E(i).Mul(I_G));
    if (!exactlyEqual(d, aI)) dualIsAI = false;
    if (!exactlyEqual(d, scaled(aI, -1).map((v) => v || 0))) dualIsMinusAI = false;
  }
  if (!dualIsAI && !dualIsMinusAI) fail('ganja .Dual is neither a*I nor -a*I');
  notes.dual = 'dual(a) = -a I, I = e1 e2 e3 e+ e- (our blade 31), computed as ganja a.Mul(I).Scale(-1); ' +
    'ganja\'s own a.Dual equals ' + (dualIsAI ? '+a I' : '-a I') + ' for this algebra' +
    (dualIsAI ? ' (i.e. the NEGATIVE of our dual)' : ' (i.e. our dual)');
  notes.gp = 'ganja a.Mul(b): geometric product';
  notes.inv = 'ganja a.Inverse: closed-form matrix-free inverse for n=5 (Hitzer-Sangwine): ' +
    'N = conj(a) inv_grade(a) rev(a); M = a N; inv = N M^ / (a N M^)_0 where M^ negates grades 1 and 4 of M; ' +
    'null when max(|a inv - 1|, |inv a - 1|) > ' + INV_TOL + '; inv_resid is that residual';
}

// ---------------------------------------------------------------- cases
const randomMV = () => { const v = new Array(NB); for (let i = 0; i < NB; ++i) v[i] = uniform(); return v; };
const ONE = ourBasis(0, 1);

const cases = [];
let invFlagged = 0;
for (let n = 0; n < N_CASES; ++n) {
  const a = randomMV(), b = randomMV();
  const ga = toGanja(a), gb = toGanja(b);
  const inv = fromGanja(ga.Inverse);
  const gInv = toGanja(inv);
  const resid = Math.max(maxAbsDiff(fromGanja(ga.Mul(gInv)), ONE), maxAbsDiff(fromGanja(gInv.Mul(ga)), ONE));
  const invOK = resid <= INV_TOL;
  if (!invOK) ++invFlagged;
  cases.push({
    a, b,
    gp: fromGanja(ga.Mul(gb)),
    op: fromGanja(ga.Wedge(gb)),
    lc: fromGanja(ga.LDot(gb)),
    dot: fromGanja(ga.Dot(gb)),
    rev: fromGanja(ga.Reverse),
    inv_grade: fromGanja(ga.Involute),
    conj: fromGanja(ga.Conjugate),
    dual: fromGanja(ga.Mul(I_G).Scale(-1)),
    inv: invOK ? inv : null,
    inv_resid: resid,
  });
}

// ---------------------------------------------------------------- versor cases
// Independent exp for validation: scaling and squaring + Taylor series.
function seriesExp(gB) {
  const B = fromGanja(gB);
  let k = 0;
  while (maxAbs(B) / 2 ** k > 1 / 64) ++k;
  const x = gB.Scale(1 / 2 ** k);
  let term = A.Scalar(1), sum = A.Scalar(1);
  for (let m = 1; m <= 30; ++m) { term = term.Mul(x).Scale(1 / m); sum = sum.Add(term); }
  for (let s = 0; s < k; ++s) sum = sum.Mul(sum);
  return fromGanja(sum);
}
const GRADE2 = [...Array(NB).keys()].filter((i) => grade(i) === 2);
const GRADE1 = [...Array(NB).keys()].filter((i) => grade(i) === 1);
const versorCases = [];
let expRejected = 0, maxExpDev = 0;
while (versorCases.length < N_VERSOR_CASES) {
  const biv = ourBasis(0, 0), b = ourBasis(0, 0);
  for (const i of GRADE2) biv[i] = uniform();
  for (const i of GRADE1) b[i] = uniform();
  const gBiv = toGanja(biv);
  const R = fromGanja(gBiv.Exp());
  const gR = toGanja(R);
  const ref = seriesExp(gBiv);
  const dev = maxAbsDiff(R, ref) / Math.max(1, maxAbs(ref));
  const normDev = maxAbsDiff(fromGanja(gR.Mul(gR.Reverse)), ONE);
  const oddPart = maxAbs(R.map((c, i) => (grade(i) % 2 ? c : 0)));
  if (!(dev <= EXP_TOL) || !(normDev <= 1e-9) || oddPart !== 0) { ++expRejected; continue; }
  maxExpDev = Math.max(maxExpDev, dev, normDev);
  versorCases.push({
    exp_biv: biv,
    exp: R,
    b,
    sandwich: fromGanja(gR.Mul(toGanja(b)).Mul(gR.Reverse)),
  });
}
notes.exp = 'ganja B.Exp() on a pure bivector (tot=5, no degenerate metric): B.Split() into commuting simple bivectors ' +
  'B_i (closed-form quadratic for the eigenvalues), then product of cos/cosh closed forms of each; ' +
  'validated against an independent scaling-and-squaring series exp (rel. tol ' + EXP_TOL + '), and exp*rev(exp) = 1';
notes.sandwich = 'ganja exp.Mul(b).Mul(exp.Reverse), b a random grade-1 vector (result is grade 1 up to rounding noise in other grades, kept as computed)';

// ---------------------------------------------------------------- output
const out = {
  generator: 'ganja.js ' + GANJA_VERSION,
  seed: SEED,
  order: ORDER,
  blade_names: [...Array(NB).keys()].map(bladeName),
  ganja_blade: [...Array(NB).keys()].map((i) => (G_SIGN[i] < 0 ? '-' : '') + GBASIS[G_IDX[i]]),
  notes,
  inv_tol: INV_TOL,
  cases,
  versor_cases: versorCases,
};
fs.writeFileSync(OUT, JSON.stringify(out) + '\n');
process.stderr.write(`gen_table.js: wrote ${OUT}: ${cases.length} cases (${invFlagged} with inv=null), ` +
  `${versorCases.length} versor cases (${expRejected} rejected bivectors); ` +
  `max inv_resid ${Math.max(...cases.map((c) => c.inv_resid)).toExponential(2)}, max exp deviation ${maxExpDev.toExponential(2)}\n`);
