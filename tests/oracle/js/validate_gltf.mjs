#!/usr/bin/env node
// validate_gltf.mjs — run the official Khronos glTF-Validator (npm `gltf-validator`) on a file.
//
//   node validate_gltf.mjs FILE.(glb|gltf) [--json] [--all] [--ignore CODE[,CODE...]]
//
// Prints a one-line summary (errors/warnings/infos/hints), a per-code count of the errors and the
// messages of the first 20 errors (--all: every message of every severity).  --ignore passes issue
// codes to the validator's `ignoredIssues` (e.g. ACCESSOR_WEIGHTS_NON_NORMALIZED).  --json writes
// the validator's full report as JSON to stdout and the human-readable text to stderr.  External resources (.bin, images) of a .gltf are read from the
// directory of FILE.
// Exit status: 0 = no errors, 1 = the validator reported errors, 2 = usage / unreadable file /
// validator failure.

import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const USAGE = 'usage: node validate_gltf.mjs FILE.(glb|gltf) [--json] [--all] [--ignore CODE[,CODE...]]';
const MAX_PRINTED_ERRORS = 20;
const SEVERITY = ['error', 'warning', 'info', 'hint'];

function usage(msg) {
  if (msg) process.stderr.write(`validate_gltf: ${msg}\n`);
  process.stderr.write(USAGE + '\n');
  process.exit(2);
}

async function main() {
  let json = false;
  let all = false;
  const ignored = [];
  const pos = [];
  const argv = process.argv.slice(2);
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--json') json = true;
    else if (a === '--ignore') {
      if (i + 1 >= argv.length) usage('--ignore needs a value');
      const codes = argv[++i].split(',').map((c) => c.trim());
      if (codes.some((c) => !/^[A-Z0-9_]+$/.test(c))) usage(`bad --ignore '${argv[i]}'`);
      ignored.push(...codes);
    }
    else if (a === '--all') all = true;
    else if (a === '-h' || a === '--help') {
      process.stdout.write(USAGE + '\n');
      process.exit(0);
    } else if (a.startsWith('--')) usage(`unknown option ${a}`);
    else pos.push(a);
  }
  if (pos.length !== 1) usage('expected exactly one FILE');
  const file = pos[0];
  let data;
  try {
    data = fs.readFileSync(file);
  } catch (e) {
    process.stderr.write(`validate_gltf: cannot read ${file}: ${e.message}\n`);
    process.exit(2);
  }
  const dir = path.dirname(path.resolve(file));
  const ext = path.extname(file).toLowerCase();
  const options = {
    uri: path.basename(file),
    maxIssues: 0, // unlimited
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        const p = path.resolve(dir, decodeURIComponent(uri));
        fs.readFile(p, (err, buf) => (err ? reject(err.toString()) : resolve(new Uint8Array(buf))));
      }),
  };
  if (ignored.length) options.ignoredIssues = ignored;
  if (ext === '.glb') options.format = 'glb';
  else if (ext === '.gltf') options.format = 'gltf';

  let report;
  try {
    report = await validator.validateBytes(new Uint8Array(data), options);
  } catch (e) {
    process.stderr.write(`validate_gltf: validator failed on ${file}: ${e && e.message ? e.message : e}\n`);
    process.exit(2);
  }

  const is = report.issues;
  const lines = [];
  lines.push(
    `${file}: ${is.numErrors} error(s), ${is.numWarnings} warning(s), ${is.numInfos} info(s), ${is.numHints} hint(s)` +
      ` [glTF-Validator ${report.validatorVersion}]` + (ignored.length ? ` (ignored: ${ignored.join(',')})` : ''),
  );
  const perCode = new Map();
  for (const m of is.messages) if (m.severity === 0) perCode.set(m.code, (perCode.get(m.code) || 0) + 1);
  if (perCode.size) lines.push(`  errors by code: ${[...perCode].map(([c, n]) => `${c} x${n}`).join(', ')}`);
  let printed = 0;
  for (const m of is.messages) {
    if (!all && m.severity !== 0) continue;
    if (!all && ++printed > MAX_PRINTED_ERRORS) {
      lines.push(`  ... ${is.numErrors - MAX_PRINTED_ERRORS} more error(s); use --all or --json to see them`);
      break;
    }
    const where = m.pointer !== undefined ? ` at ${m.pointer}` : m.offset !== undefined ? ` at byte ${m.offset}` : '';
    lines.push(`  ${SEVERITY[m.severity] ?? m.severity}: ${m.code}: ${m.message}${where}`);
  }
  const text = lines.join('\n') + '\n';
  if (json) {
    process.stdout.write(JSON.stringify(report, null, 2) + '\n');
    process.stderr.write(text);
  } else {
    process.stdout.write(text);
  }
  process.exit(is.numErrors > 0 ? 1 : 0);
}

main().catch((e) => {
  process.stderr.write(`validate_gltf: ${e && e.stack ? e.stack : e}\n`);
  process.exit(2);
});
