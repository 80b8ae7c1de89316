#!/usr/bin/env python3
"""Field sweep: run the cgamesh CLI over every model a user might bring and report what each
command does with each file (issue #33).

For every model file under the data directories (by default ../shared/data and Debian's
assimp-testmodels; every extension the CLI's Assimp reads, auxiliary files skipped) it runs, in a
work directory of its own:

  info --json                      the bind-pose box, clips and counts the tools below use
  pose                             the bind pose, and mid-clip when the file has a clip, to .ply
  convert                          to .glb; `info` on the written .glb must load it again with the
                                   same meshes, vertices, faces, joints, clips and clip durations
  render                           a PNG in OUT/png (OUT/index.html shows them all)
  cut --cap                        through the box centre, normal to the box's longest axis
  tear                             a short stroke across the front (+z) near the box centre's line
                                   of sight, through the bind-pose surface (see tear_args)
  drill --wall                     along the box's shortest axis through the centre, outside to outside

and checks every written glTF with the Khronos validator the tests use (tests/oracle/js), when
node and its npm packages are installed. The report (stdout, OUT/report.md, OUT/report.json)
has one row per file and one cell per command: ok, the number of warnings, the exit code and
the first line of the error, TIMEOUT, or CRASH (a signal or an exit code that
apps/cli/exit_codes.hpp does not define). The work directories of files with a problem stay in
OUT/work, so that the command lines quoted in the report run again as they are.

Exit status: 0 when every command ended within the time limit with a documented exit code
(refusals of unreadable files included); 1 when there was a crash, an undocumented exit code, a
timeout, or a written file that does not load again (or is missing); 2 for a bad command line.
Reload mismatches and validator errors are listed but do not change the exit status.

Standard library only; a developer/QA tool (`make sweep`), not part of `make test`.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import ctypes
import ctypes.util
import html
import json
import math
import os
import re
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
VALIDATOR = REPO / "tests" / "oracle" / "js" / "validate_gltf.mjs"

# Files of the formats Assimp reads that are not models on their own: the companions of a
# model (an OGRE skeleton or material, MD5 animations and cameras), read with it.
AUXILIARY_SUFFIXES = (".md5anim", ".md5camera", ".skeleton", ".skeleton.xml", ".material", ".mtl", ".bin")
# What Assimp 5 reads, for when the library cannot be asked (aiGetExtensionList).
FALLBACK_EXTENSIONS = (
    ".3d .3ds .3mf .ac .ac3d .acc .amf .ase .ask .assbin .b3d .blend .bsp .bvh .cob .csm .dae .dxf .enff "
    ".fbx .glb .gltf .hmp .ifc .ifczip .iqm .irr .irrmesh .lwo .lws .lxo .md2 .md3 .md5anim .md5camera "
    ".md5mesh .mdc .mdl .mesh .mesh.xml .mot .ms3d .ndo .nff .obj .off .ogex .pk3 .ply .pmx .prj .q3o .q3s "
    ".raw .scn .sib .smd .step .stl .stp .ter .uc .vta .x .x3d .x3db .xgl .xml .zae .zgl"
).split()

COLUMNS = ("info", "pose", "pose_mid", "convert", "reload", "render", "cut", "tear", "drill", "gltf_valid")
# Reload comparison: what a written .glb must give back (durations within this many seconds).
DURATION_TOLERANCE = 1e-4
PNG_SIZE = "480x360"


def documented_exit_codes() -> dict[int, str]:
    """The exit codes apps/cli/exit_codes.hpp defines (code -> constant names)."""
    codes: dict[int, str] = {}
    header = REPO / "apps" / "cli" / "exit_codes.hpp"
    try:
        for name, value in re.findall(r"constexpr\s+int\s+(kExit\w+)\s*=\s*(\d+)", header.read_text()):
            codes[int(value)] = (codes[int(value)] + "/" if int(value) in codes else "") + name
    except OSError:
        pass
    return codes or {0: "kExitOk", 1: "kExitInternal", 2: "kExitBadArguments", 3: "kExitBadInput", 4: "kExitImpossible"}


def loader_extensions(cli: Path) -> tuple[list[str], str]:
    """The extensions the CLI's Assimp reads (lower case, with the dot) and where they came from."""
    lib = None
    try:
        ldd = subprocess.run(["ldd", str(cli)], capture_output=True, text=True, timeout=30).stdout
        m = re.search(r"(libassimp\.so[.\d]*)\s+=>\s+(\S+)", ldd)
        lib = m.group(2) if m else None
    except (OSError, subprocess.SubprocessError):
        pass
    lib = lib or ctypes.util.find_library("assimp")
    if lib:
        try:

            class AiString(ctypes.Structure):
                _fields_ = [("length", ctypes.c_uint32), ("data", ctypes.c_char * 1024)]

            s = AiString()
            ctypes.CDLL(lib).aiGetExtensionList(ctypes.byref(s))
            exts = [e.strip().lstrip("*").lower() for e in s.data[: s.length].decode().split(";")]
            exts = [e for e in exts if e.startswith(".")]
            if exts:
                return sorted(set(exts)), f"aiGetExtensionList of {lib}"
        except (OSError, AttributeError, UnicodeDecodeError):
            pass
    return sorted(FALLBACK_EXTENSIONS), "built-in list (Assimp 5)"


def assimp_testmodels_dir() -> Path | None:
    """The root of Debian's assimp-testmodels (the deepest directory all its files share)."""
    try:
        listing = subprocess.run(["dpkg", "-L", "assimp-testmodels"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    files = [p for p in listing.stdout.splitlines() if p.startswith("/") and Path(p).is_file()]
    if listing.returncode != 0 or not files:
        return None
    files = [p for p in files if "/doc/" not in p]  # the package's copyright and changelog
    return Path(os.path.commonpath(files)) if files else None


@dataclass
class Model:
    path: Path
    name: str  # shown in the report: the data directory's label and the path inside it

    @property
    def slug(self) -> str:
        return re.sub(r"[^A-Za-z0-9._-]+", "_", self.name.replace("/", "__"))


def is_model(name: str, extensions: list[str]) -> bool:
    lower = name.lower()
    if lower.endswith(AUXILIARY_SUFFIXES):
        return False
    return any(lower.endswith(e) for e in extensions)


def find_models(roots: list[tuple[Path, str]], extensions: list[str]) -> list[Model]:
    models: list[Model] = []
    seen: set[Path] = set()
    for root, label in roots:
        if root.is_file():
            candidates = [(root, f"{label}")]
        else:
            candidates = []
            for dirpath, dirnames, filenames in os.walk(root):
                dirnames.sort()
                for f in sorted(filenames):
                    if is_model(f, extensions):
                        p = Path(dirpath) / f
                        candidates.append((p, f"{label}/{p.relative_to(root).as_posix()}"))
        for p, name in candidates:
            real = p.resolve()
            if real not in seen:
                seen.add(real)
                models.append(Model(p, name))
    return models


# ---------------------------------------------------------------------------------------------
# Running one command


@dataclass
class Run:
    argv: list[str]
    rc: int | None = None  # None: killed at the time limit
    stdout: str = ""
    stderr: str = ""
    seconds: float = 0.0

    @property
    def timed_out(self) -> bool:
        return self.rc is None

    def json(self) -> dict | None:
        try:
            value = json.loads(self.stdout)
        except ValueError:
            return None
        return value if isinstance(value, dict) else None


def run(argv: list[str], cwd: Path, timeout: float) -> Run:
    r = Run([str(a) for a in argv])
    start = time.monotonic()
    # A session of its own, so that a command past its time limit goes with all it started.
    proc = subprocess.Popen(r.argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        r.rc = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
    r.seconds = time.monotonic() - start
    r.stdout = out.decode("utf-8", "replace")
    r.stderr = err.decode("utf-8", "replace")
    return r


@dataclass
class Cell:
    """What one command did with one file."""

    # ok, warn, refused (a documented non-zero exit), timeout, crash, bad (an output missing or not
    # loading again), mismatch, invalid, skipped, n/a
    kind: str
    text: str  # the table cell
    message: str = ""  # for the summary
    warnings: list[str] = field(default_factory=list)
    command: str = ""
    seconds: float = 0.0

    def to_json(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if v not in ("", [])}


FAILING_KINDS = ("timeout", "crash", "bad")  # make the sweep exit 1
PROBLEM_KINDS = FAILING_KINDS + ("mismatch", "invalid", "refused", "skipped")


def first_error_line(stderr: str) -> str:
    """cgamesh's own error line; else the first other line (a reader may print on stderr first)."""
    lines = [line.strip() for line in stderr.splitlines() if line.strip() and not line.startswith("cgamesh: warning:")]
    own = [line for line in lines if line.startswith("cgamesh: ")]
    return (own or lines or ["(no message on stderr)"])[0][:300]


def classify(r: Run, codes: dict[int, str], timeout: float) -> Cell:
    command = shlex.join(r.argv)
    if r.timed_out:
        return Cell("timeout", "TIMEOUT", f"no answer within {timeout:g} s", command=command, seconds=r.seconds)
    if r.rc is not None and r.rc < 0:
        try:
            name = signal.Signals(-r.rc).name
        except ValueError:
            name = f"signal {-r.rc}"
        return Cell("crash", f"CRASH {name}", f"killed by {name}: {first_error_line(r.stderr)}", command=command,
                    seconds=r.seconds)
    if r.rc not in codes:
        return Cell("crash", f"CRASH exit {r.rc}", f"undocumented exit code {r.rc}: {first_error_line(r.stderr)}",
                    command=command, seconds=r.seconds)
    data = r.json()
    if data is not None and isinstance(data.get("warnings"), list):
        warnings = [str(w) for w in data["warnings"]]
    else:
        warnings = [line[len("cgamesh: warning:"):].strip() for line in r.stderr.splitlines()
                    if line.startswith("cgamesh: warning:")]
    if r.rc != 0:
        line = first_error_line(r.stderr)
        return Cell("refused", f"exit {r.rc}: {line}", f"exit {r.rc} ({codes[r.rc]}): {line}", warnings, command,
                    r.seconds)
    if warnings:
        return Cell("warn", f"{len(warnings)} warn", "", warnings, command, r.seconds)
    return Cell("ok", "ok", "", [], command, r.seconds)


# ---------------------------------------------------------------------------------------------
# The tools' placement from the bind-pose box


def fmt(*values: float) -> str:
    return ",".join(f"{v:.9g}" for v in values)


@dataclass
class Box:
    lo: list[float]
    hi: list[float]

    @staticmethod
    def of(info: dict | None) -> Box:
        try:
            b = info["bounding_box"]  # type: ignore[index]
            lo, hi = [float(v) for v in b["min"]], [float(v) for v in b["max"]]
            if len(lo) == 3 and len(hi) == 3 and all(math.isfinite(v) for v in lo + hi) and all(
                    l <= h for l, h in zip(lo, hi)):
                return Box(lo, hi)
        except (TypeError, KeyError, ValueError):
            pass
        return Box([-0.5] * 3, [0.5] * 3)  # no box: the tools still run, to see how they refuse

    @property
    def centre(self) -> list[float]:
        return [(l + h) / 2 for l, h in zip(self.lo, self.hi)]

    @property
    def extent(self) -> list[float]:
        return [h - l for l, h in zip(self.lo, self.hi)]

    @property
    def diagonal(self) -> float:
        return math.sqrt(sum(e * e for e in self.extent)) or 1.0


def cut_args(box: Box) -> list[str]:
    """The plane through the centre, normal to the longest axis."""
    axis = max(range(3), key=lambda i: box.extent[i])
    normal = [1.0 if i == axis else 0.0 for i in range(3)]
    return ["--plane", fmt(*normal, box.centre[axis]), "--cap"]


def read_ply(path: Path) -> tuple[list[tuple[float, ...]], list[tuple[int, ...]]]:
    """The positions and triangles of a PLY that `cgamesh pose` wrote (binary little endian,
    float x y z first, faces as uchar-counted int lists); empty when it is not one."""
    try:
        data = path.read_bytes()
        end = data.index(b"end_header\n") + len(b"end_header\n")
        header = data[:end].decode("ascii").splitlines()
        vertex_line = next(i for i, line in enumerate(header) if line.startswith("element vertex"))
        count = int(header[vertex_line].split()[2])
        props = []
        for line in header[vertex_line + 1:]:
            if not line.startswith("property"):
                break
            props.append(line)
        faces_line = next(line for line in header if line.startswith("element face"))
        if "binary_little_endian" not in header[1] or props[:3] != [f"property float {c}" for c in "xyz"]:
            return [], []
        stride = 4 * len(props)
        vertices = [struct.unpack_from("<3f", data, end + i * stride) for i in range(count)]
        offset, faces = end + count * stride, []
        for _ in range(int(faces_line.split()[2])):
            n = data[offset]
            face = struct.unpack_from(f"<{n}i", data, offset + 1)
            offset += 1 + 4 * n
            faces += [(face[0], face[k], face[k + 1]) for k in range(1, n - 1)]
        return vertices, faces
    except (OSError, ValueError, StopIteration, UnicodeDecodeError, struct.error, IndexError):
        return [], []


def first_hit(surface, axis: int, point: tuple[float, float], across: tuple[int, int]) -> float | None:
    """The largest coordinate along `axis` at which the line through `point` (coordinates
    `across`) crosses a triangle: where a blade coming from the + side meets the surface."""
    vertices, faces = surface
    i, j = across
    px, py = point
    best = None
    for f in faces:
        a, b, c = vertices[f[0]], vertices[f[1]], vertices[f[2]]
        d1 = (b[i] - a[i]) * (py - a[j]) - (b[j] - a[j]) * (px - a[i])
        d2 = (c[i] - b[i]) * (py - b[j]) - (c[j] - b[j]) * (px - b[i])
        d3 = (a[i] - c[i]) * (py - c[j]) - (a[j] - c[j]) * (px - c[i])
        total = d1 + d2 + d3
        if total == 0 or (d1 < 0 or d2 < 0 or d3 < 0) and (d1 > 0 or d2 > 0 or d3 > 0):
            continue
        depth = (d2 * a[axis] + d3 * b[axis] + d1 * c[axis]) / total
        best = depth if best is None or depth > best else best
    return best


def tear_args(box: Box, surface) -> list[str]:
    """Four blade steps across the front (+z, what `render --view front` sees: the blade comes
    from outside the box in front and ends just behind the surface) through the box centre's
    line of sight. The centre itself misses most figures (between the legs, arms out), so when the
    bind pose is known the stroke is a short one through the centre's line if it meets the
    surface, else through the surface vertex nearest that line, each step checked to meet a
    triangle; for a model that a blade from the front does not meet there (flat along z), from
    the top (+y), then the right (+x)."""
    c, d = box.centre, box.diagonal
    vertices, faces = surface
    for axis in (2, 1, 0) if faces else ():
        across = tuple(k for k in range(3) if k != axis)
        nearest = min(vertices, key=lambda v: (v[across[0]] - c[across[0]]) ** 2 + (v[across[1]] - c[across[1]]) ** 2)
        for p, along in [(p, along) for p in (c, nearest) for along in across]:
            for half in (0.03 * d, 0.01 * d):
                steps, depths = [], []
                for k in range(4):
                    q = list(p)
                    q[along] += -half + 2 * half * k / 3
                    hit = first_hit(surface, axis, (q[across[0]], q[across[1]]), across)
                    if hit is None:
                        break
                    steps.append(q)
                    depths.append(hit)
                if len(steps) < 4:
                    continue
                args = []
                for q in steps:
                    handle, tip = list(q), list(q)
                    handle[axis], tip[axis] = box.hi[axis] + 0.5 * d, min(depths) - 0.02 * d
                    args += ["--scalpel", fmt(*handle, *tip)]
                return args + ["--open", fmt(0.005 * d)]
    half = 0.03 * d
    args = []
    for k in range(4):
        x = c[0] - half + 2 * half * k / 3
        args += ["--scalpel", fmt(x, c[1], box.hi[2] + 0.5 * d, x, c[1], c[2])]
    return args + ["--open", fmt(0.005 * d)]


def drill_args(box: Box) -> list[str]:
    """Along the shortest axis through the centre, from outside the box to outside it."""
    axis = min(range(3), key=lambda i: box.extent[i])
    c, e, d = box.centre, box.extent, box.diagonal
    reach = e[axis] / 2 + 0.25 * d
    base = [c[i] - (reach if i == axis else 0) for i in range(3)]
    tip = [c[i] + (reach if i == axis else 0) for i in range(3)]
    others = [e[i] for i in range(3) if i != axis]
    radius = 0.05 * min(others) if min(others) > 0.01 * d else 0.02 * d
    return ["--base", fmt(*base), "--tip", fmt(*tip), "--radius", fmt(radius), "--wall"]


# ---------------------------------------------------------------------------------------------
# Reload comparison and validation


def info_counts(info: dict) -> dict:
    clips = info.get("animations") or []
    return {
        "meshes": len(info.get("meshes") or []),
        "vertices": info.get("vertices"),
        "faces": info.get("triangles"),
        "skinned joints": info.get("skinned_joints"),
        "clips": len(clips),
        "durations": [c.get("duration") for c in clips],
    }


def compare_infos(before: dict, after: dict) -> list[str]:
    a, b = info_counts(before), info_counts(after)
    diffs = []
    for key in ("meshes", "vertices", "faces", "skinned joints", "clips"):
        if a[key] != b[key]:
            diffs.append(f"{key} {a[key]}->{b[key]}")
    if a["clips"] == b["clips"]:
        for i, (x, y) in enumerate(zip(a["durations"], b["durations"])):
            if not (isinstance(x, (int, float)) and isinstance(y, (int, float))) or abs(x - y) > DURATION_TOLERANCE:
                diffs.append(f"clip {i} duration {x}->{y}")
    return diffs


class Validator:
    def __init__(self, timeout: float):
        node = shutil.which("node")
        have = node and VALIDATOR.exists() and (VALIDATOR.parent / "node_modules" / "gltf-validator").is_dir()
        self.node = node if have else None
        self.timeout = timeout
        self.why_not = "" if have else (
            "node is not installed" if not node else
            f"{VALIDATOR.parent.relative_to(REPO)}/node_modules is missing (run scripts/install-deps.sh)")

    def check(self, file: Path, cwd: Path) -> tuple[str, str, str]:
        """(kind, short, message) for one glTF: ok, invalid (validator errors), or crash/timeout of the validator."""
        r = run([self.node, VALIDATOR, file], cwd, self.timeout)
        if r.timed_out:
            return "invalid", "validator timeout", f"{file.name}: the validator gave no answer in {self.timeout:g} s"
        if r.rc == 0:
            return "ok", "", ""
        lines = (r.stdout + r.stderr).strip().splitlines()
        summary = "; ".join(line.strip() for line in lines[1:4]) or (lines[0] if lines else f"exit {r.rc}")
        return "invalid", f"{file.name}", f"{file.name}: {summary[:400]}"


# ---------------------------------------------------------------------------------------------
# One file


@dataclass
class Result:
    model: Model
    cells: dict[str, Cell] = field(default_factory=dict)
    png: str = ""
    seconds: float = 0.0
    workdir: Path | None = None

    @property
    def problems(self) -> list[tuple[str, Cell]]:
        return [(c, cell) for c, cell in self.cells.items() if cell.kind in PROBLEM_KINDS]

    @property
    def failing(self) -> bool:
        return any(cell.kind in FAILING_KINDS for cell in self.cells.values())


class Sweep:
    def __init__(self, args: argparse.Namespace):
        self.cli = Path(args.cli).resolve()
        self.out = Path(args.out).resolve()
        self.timeout = args.timeout
        self.codes = documented_exit_codes()
        self.validator = Validator(args.timeout)
        self.keep = args.keep
        # The CLI's own guard against readers that hang, inside the sweep's limit: a hang while
        # loading is the documented exit 3, a hang anywhere else a TIMEOUT.
        self.cli_prefix = [str(self.cli), "--load-timeout", fmt(max(1.0, 0.75 * args.timeout))]

    def cli_run(self, work: Path, *args: str | Path) -> Run:
        return run(self.cli_prefix + [str(a) for a in args], work, self.timeout)

    def command(self, result: Result, column: str, work: Path, args: list, outputs: list[Path]) -> Run:
        r = self.cli_run(work, *args)
        cell = classify(r, self.codes, self.timeout)
        if cell.kind in ("ok", "warn"):
            missing = [p.name for p in outputs if not p.is_file() or p.stat().st_size == 0]
            if missing:
                cell = Cell("bad", "NO OUTPUT", f"exit 0 but did not write {', '.join(missing)}", cell.warnings,
                            cell.command, cell.seconds)
        result.cells[column] = cell
        return r

    def sweep_file(self, model: Model) -> Result:
        start = time.monotonic()
        result = Result(model)
        work = self.out / "work" / model.slug
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        result.workdir = work
        src = model.path.resolve()

        r = self.command(result, "info", work, ["info", "--json", src], [])
        info = r.json() if r.rc == 0 else None
        if result.cells["info"].kind == "timeout":
            for c in COLUMNS[1:]:
                result.cells[c] = Cell("skipped", "skipped", "not run: info timed out")
            result.seconds = time.monotonic() - start
            return result
        box = Box.of(info)

        self.command(result, "pose", work, ["pose", src, "-o", work / "bind.ply", "--json"], [work / "bind.ply"])
        clips = (info or {}).get("animations") or []
        if clips:
            t = float(clips[0].get("duration") or 0.0) / 2
            self.command(result, "pose_mid", work,
                         ["pose", src, "--anim", "0", "--time", fmt(t), "-o", work / "mid.ply", "--json"],
                         [work / "mid.ply"])
        else:
            result.cells["pose_mid"] = Cell("n/a", "n/a", "no clip" if info else "info failed")

        gltfs: list[Path] = []
        converted = work / "converted.glb"
        self.command(result, "convert", work, ["convert", src, "-o", converted, "--json"], [converted])
        if result.cells["convert"].kind in ("ok", "warn"):
            gltfs.append(converted)
            r = self.command(result, "reload", work, ["info", "--json", converted], [])
            cell = result.cells["reload"]
            if cell.kind == "refused":  # a written file must load again
                result.cells["reload"] = Cell("bad", f"NO RELOAD exit {r.rc}",
                                              f"the written .glb does not load: {cell.message}", cell.warnings,
                                              cell.command, cell.seconds)
            elif cell.kind in ("ok", "warn") and info is not None and r.json() is not None:
                diffs = compare_infos(info, r.json() or {})
                if diffs:
                    result.cells["reload"] = Cell("mismatch", "MISMATCH " + "; ".join(diffs),
                                                  "the written .glb loads with other counts: " + "; ".join(diffs),
                                                  cell.warnings, cell.command, cell.seconds)
        else:
            result.cells["reload"] = Cell("n/a", "n/a", "nothing converted")

        png = self.out / "png" / f"{model.slug}.png"
        self.command(result, "render", work, ["render", src, "-o", png, "--size", PNG_SIZE, "--json"], [png])
        if png.is_file():
            result.png = f"png/{png.name}"

        pieces = [work / "cut_a.glb", work / "cut_b.glb"]
        self.command(result, "cut", work, ["cut", src, *cut_args(box), "-o", *pieces, "--json"], pieces)
        torn = work / "torn.glb"
        tear = tear_args(box, read_ply(work / "bind.ply"))
        self.command(result, "tear", work, ["tear", src, *tear, "-o", torn, "--json"], [torn])
        drilled = work / "drilled.glb"
        self.command(result, "drill", work, ["drill", src, *drill_args(box), "-o", drilled, "--json"], [drilled])
        for column, files in (("cut", pieces), ("tear", [torn]), ("drill", [drilled])):
            if result.cells[column].kind in ("ok", "warn"):
                gltfs += files

        if not self.validator.node:
            result.cells["gltf_valid"] = Cell("n/a", "not checked", self.validator.why_not)
        elif not gltfs:
            result.cells["gltf_valid"] = Cell("n/a", "n/a", "no glTF written")
        else:
            checks = [self.validator.check(f, work) for f in gltfs]
            bad = [c for c in checks if c[0] != "ok"]
            if bad:
                result.cells["gltf_valid"] = Cell("invalid", "INVALID " + ", ".join(b[1] for b in bad),
                                                  " | ".join(b[2] for b in bad),
                                                  command=shlex.join(["node", str(VALIDATOR), str(gltfs[0])]))
            else:
                result.cells["gltf_valid"] = Cell("ok", f"ok ({len(gltfs)})")

        result.seconds = time.monotonic() - start
        # Keep the outputs (and the command lines' paths) of files with a problem, to look into.
        if not self.keep and not result.problems:
            shutil.rmtree(work, ignore_errors=True)
            result.workdir = None
        return result


# ---------------------------------------------------------------------------------------------
# The report


def normalise_warning(text: str, model: Model, work: Path | None) -> str:
    for p in (str(model.path.resolve()), str(model.path)):
        if text.startswith(p + ": "):
            text = text[len(p) + 2:]
        text = text.replace(p, "MODEL")
    if work is not None:
        text = text.replace(str(work), "WORK")
    return re.sub(r"[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", "N", text)


def md_cell(text: str) -> str:
    text = text.replace("|", "\\|").replace("\n", " ")
    return text if len(text) <= 70 else text[:67] + "..."


def build_report(results: list[Result], sweep: Sweep, meta: dict) -> tuple[str, dict, int]:
    lines = ["# cgamesh field sweep", ""]
    lines.append(f"- CLI: `{sweep.cli}`")
    lines.append(f"- data: {', '.join(f'`{d}`' for d in meta['data'])}")
    lines.append(f"- extensions read ({meta['extensions_source']}): {' '.join(meta['extensions'])}")
    lines.append(f"- files: {len(results)}; time limit per command: {sweep.timeout:g} s; jobs: {meta['jobs']}; "
                 f"wall time: {meta['seconds']:.1f} s")
    lines.append("- documented exit codes: " + ", ".join(f"{c} ({n})" for c, n in sorted(sweep.codes.items())))
    lines.append("- glTF validation: " + ("Khronos glTF-Validator (tests/oracle/js)" if sweep.validator.node else
                                          f"skipped: {sweep.validator.why_not}"))
    lines.append("")
    lines.append("| file | " + " | ".join(COLUMNS) + " | s |")
    lines.append("|---" * (len(COLUMNS) + 2) + "|")
    for res in results:
        cells = [md_cell(res.cells[c].text) if c in res.cells else "" for c in COLUMNS]
        lines.append(f"| {md_cell(res.model.name)} | " + " | ".join(cells) + f" | {res.seconds:.1f} |")

    counts: dict[str, int] = {}
    for res in results:
        for cell in res.cells.values():
            counts[cell.kind] = counts.get(cell.kind, 0) + 1
    lines += ["", "## Totals", "", ", ".join(f"{k}: {v}" for k, v in sorted(counts.items()))]

    lines += ["", "## Problems", ""]
    lines.append("Every cell that is not ok or warnings only (refusals with a documented code included). "
                 "FAILING marks what makes the sweep fail.")
    lines.append("")
    problems = [(res, column, cell) for res in results for column, cell in res.problems]
    problems.sort(key=lambda p: p[2].kind not in FAILING_KINDS)  # what fails the sweep first
    for res, column, cell in problems:
        mark = "FAILING " if cell.kind in FAILING_KINDS else ""
        lines.append(f"- {mark}**{res.model.name}** `{column}` [{cell.kind}]: {cell.message}")
        if cell.command:
            lines.append(f"  - `{cell.command}`")
    if not problems:
        lines.append("(none)")

    warnings: dict[str, dict] = {}
    for res in results:
        for column, cell in res.cells.items():
            for w in cell.warnings:
                key = normalise_warning(w, res.model, res.workdir)
                entry = warnings.setdefault(key, {"count": 0, "files": set(), "commands": set()})
                entry["count"] += 1
                entry["files"].add(res.model.name)
                entry["commands"].add(column)
    lines += ["", "## Warnings", "", "| count | files | text (numbers as N) |", "|---|---|---|"]
    for key, entry in sorted(warnings.items(), key=lambda kv: (-kv[1]["count"], kv[0])):
        lines.append(f"| {entry['count']} | {len(entry['files'])} | {key.replace('|', '/')} |")

    failing = [r.model.name for r in results if r.failing]
    status = 1 if failing else 0
    if failing:
        lines += ["", f"Sweep status: 1 ({len(failing)} file(s) with a crash, an undocumented exit code, a timeout, "
                  "or a written file that is missing or does not load again)"]
    else:
        lines += ["", "Sweep status: 0 (every command ended with a documented exit code within its time limit)"]
    report = {
        **meta,
        "cli": str(sweep.cli),
        "timeout": sweep.timeout,
        "exit_codes": {str(c): n for c, n in sweep.codes.items()},
        "validator": bool(sweep.validator.node),
        "validator_missing": sweep.validator.why_not,
        "files": [{"file": r.model.name, "path": str(r.model.path), "seconds": round(r.seconds, 3), "png": r.png,
                   "workdir": str(r.workdir) if r.workdir else "",
                   "cells": {c: cell.to_json() for c, cell in r.cells.items()}}
                  for r in results],
        "totals": counts,
        "warnings": [{"text": k, "count": v["count"], "files": sorted(v["files"]), "commands": sorted(v["commands"])}
                     for k, v in sorted(warnings.items(), key=lambda kv: (-kv[1]["count"], kv[0]))],
        "failing_files": failing,
        "status": status,
    }
    return "\n".join(lines) + "\n", report, status


def write_html(results: list[Result], path: Path, title: str) -> None:
    colour = {"ok": "#cfc", "warn": "#ffd", "refused": "#fdb", "n/a": "#eee", "skipped": "#eee", "mismatch": "#fbb",
              "invalid": "#fbb", "timeout": "#f77", "crash": "#f77", "bad": "#f77"}
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>" + html.escape(title) + "</title><style>"
        "body{font-family:sans-serif;margin:1em}figure{display:inline-block;vertical-align:top;width:490px;"
        "margin:4px;border:1px solid #ccc;padding:4px}img{width:480px;height:360px;background:#f4f4f4}"
        ".none{width:480px;height:360px;display:flex;align-items:center;justify-content:center;background:#f4f4f4;"
        "color:#900;text-align:center}figcaption{font-size:12px}span{display:inline-block;margin:1px;padding:0 3px;"
        "border-radius:3px}</style></head><body><h1>" + html.escape(title) + "</h1>"
    ]
    for res in results:
        parts.append("<figure>")
        if res.png:
            parts.append(f"<a href='{html.escape(res.png)}'><img src='{html.escape(res.png)}' loading='lazy' "
                         f"alt='{html.escape(res.model.name)}'></a>")
        else:
            render = res.cells.get("render")
            parts.append(f"<div class='none'>no picture<br>{html.escape(render.message if render else '')}</div>")
        parts.append(f"<figcaption><b>{html.escape(res.model.name)}</b><br>")
        for c in COLUMNS:
            cell = res.cells.get(c)
            if cell:
                tip = html.escape(cell.message or "; ".join(cell.warnings), quote=True)
                parts.append(f"<span style='background:{colour.get(cell.kind, '#fff')}' title='{tip}'>"
                             f"{html.escape(c)}: {html.escape(md_cell(cell.text))}</span>")
        parts.append("</figcaption></figure>")
    parts.append("</body></html>\n")
    path.write_text("".join(parts))


# ---------------------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="Default data: ../shared/data (next to the repository) and the install "
                                     "directory of Debian's assimp-testmodels.")
    parser.add_argument("--cli", default=str(REPO / "build" / "apps" / "cli" / "cgamesh"), help="the cgamesh CLI")
    parser.add_argument("--data", action="append", metavar="DIR",
                        help="a directory to search for models (or one model file); repeatable; replaces the defaults")
    parser.add_argument("--out", default=str(REPO / "build" / "sweep"),
                        help="report, pictures and kept work directories (default build/sweep)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per command (default 60)")
    parser.add_argument("--jobs", type=int, default=2, help="files swept at once (default 2)")
    parser.add_argument("--limit", type=int, help="sweep at most this many files (after --filter)")
    parser.add_argument("--filter", metavar="REGEX", help="only files whose shown name matches (re.search)")
    parser.add_argument("--keep", action="store_true", help="keep every work directory, not only those with a problem")
    parser.add_argument("--list", action="store_true", help="list the files that would be swept and exit")
    args = parser.parse_args(argv)
    if args.timeout <= 0 or args.jobs < 1 or (args.limit is not None and args.limit < 0):
        parser.error("--timeout, --jobs and --limit must be positive")
    try:
        pattern = re.compile(args.filter) if args.filter else None
    except re.error as e:
        parser.error(f"--filter: {e}")

    cli = Path(args.cli)
    if not (cli.is_file() and os.access(cli, os.X_OK)):
        parser.error(f"--cli {cli}: not an executable file (build it: make build)")
    if args.data:
        roots = []
        for d in args.data:
            p = Path(d)
            if not p.exists():
                parser.error(f"--data {d}: no such file or directory")
            roots.append((p, p.name))
    else:
        roots = []
        shared = REPO.parent / "shared" / "data"
        if shared.is_dir():
            roots.append((shared, "data"))
        assimp = assimp_testmodels_dir()
        if assimp:
            roots.append((assimp, "assimp-testmodels"))
        if not roots:
            parser.error("no data: neither ../shared/data nor assimp-testmodels is there; give --data DIR")
    extensions, source = loader_extensions(cli)
    models = find_models(roots, extensions)
    if pattern:
        models = [m for m in models if pattern.search(m.name)]
    if args.limit is not None:
        models = models[: args.limit]
    if args.list:
        for m in models:
            print(f"{m.name}\t{m.path}")
        return 0

    sweep = Sweep(args)
    for sub in ("png", "work"):
        shutil.rmtree(sweep.out / sub, ignore_errors=True)
        (sweep.out / sub).mkdir(parents=True)
    start = time.monotonic()
    results: list[Result | None] = [None] * len(models)
    lock = threading.Lock()
    done = 0

    def one(i: int) -> None:
        nonlocal done
        res = sweep.sweep_file(models[i])
        results[i] = res
        with lock:
            done += 1
            worst = ", ".join(f"{c}: {cell.text}" for c, cell in res.problems) or "ok"
            print(f"[{done}/{len(models)}] {res.model.name} ({res.seconds:.1f} s): {md_cell(worst)}", file=sys.stderr,
                  flush=True)

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for f in [pool.submit(one, i) for i in range(len(models))]:
            f.result()
    swept = [r for r in results if r is not None]
    meta = {"data": [str(r[0]) for r in roots], "extensions": extensions, "extensions_source": source,
            "jobs": args.jobs, "seconds": round(time.monotonic() - start, 1)}
    text, report, status = build_report(swept, sweep, meta)
    (sweep.out / "report.md").write_text(text)
    (sweep.out / "report.json").write_text(json.dumps(report, indent=1) + "\n")
    write_html(swept, sweep.out / "index.html", f"cgamesh field sweep: {len(swept)} files")
    if not any((sweep.out / "work").iterdir()):
        (sweep.out / "work").rmdir()
    sys.stdout.write(text)
    print(f"field_sweep: report in {sweep.out}/report.md, pictures in {sweep.out}/index.html", file=sys.stderr)
    return status


if __name__ == "__main__":
    sys.exit(main())
