"""The multi-block route (SPEC 10) on OpenFOAM's own tutorial blockings, beside blockMesh.

    .venv/bin/python benchmarks/foam_blockings.py shared/foam      # one folder a case

Each folder under the argument holds a ``blockMeshDict`` (copied from OpenFOAM's tutorials;
fetched data, never committed). The dict is expanded by ``foamDictionary -expand`` (its
``$macros``), read (vertices, blocks with counts and gradings, arc and polyLine edges,
patches) and cut to its 2D section: the axis along which its vertices take two values is
dropped. The section becomes SPEC 10 inputs: the boundary rings (``boundary.vtp``), every
edge between two blocks as a block edge (``edges.vtp``), one ``--cells X,Y=N`` item per chain
of opposite block sides (the dict's count), ``--spacing X,Y=H`` on every block side next to
which the dict's grading makes the cells smaller than 0.8 of the even cell (H the dict's
cell there), and ``--patch X,Y=NAME:TYPE`` on each patch face. pinn-mesh (default and
``--method elliptic``) then writes an OpenFOAM case; blockMesh meshes the original; checkMesh
measures both. Printed per case and method: accepted or the refusal's line, folded cells,
mean / worst MaxIncludedAngle, checkMesh's largest non-orthogonality (ours against
blockMesh's) and the cells, and what the SPEC cannot express of the dict (notes).
Needs OpenFOAM (``/usr/share/openfoam/etc/bashrc``: foamDictionary, blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from pinn_engine.io.export.openfoam import case_files

ROOT = Path(__file__).resolve().parents[1]
FOAM_RC = "/usr/share/openfoam/etc/bashrc"  # where OpenFOAM v1912 is installed here
OUT = ROOT / "out" / "foam_blockings"  # the cases' inputs, grids and logs
MAX_GROWTH = 1.25  # SPEC 10's largest ratio of neighbouring cells along a graded chain
FINE_CELL = 0.8  # a graded end cell under this fraction of the even cell gets --spacing
ARC_STEP = math.radians(1.0)  # the largest turn between two sampled points of an arc
METHODS = {  # the default, the all-block Winslow grid, and it with blockMesh's drawn interfaces
    "pinn": [],
    "elliptic": ["--method", "elliptic"],
    "elliptic fixed": ["--method", "elliptic", "--interfaces", "fixed"],
}
RUN_LIMIT = 600  # seconds a pinn-mesh run may take before it counts as failed
PATCH_TYPES = {
    "wall": "wall",
    "patch": "patch",
    "symmetryPlane": "symmetry",
    "symmetry": "symmetry",
}
# hex-local directions: its vertex pairs along each (blockMesh's edge numbering)
HEX_EDGES = (
    ((0, 1), (3, 2), (7, 6), (4, 5)),
    ((0, 3), (1, 2), (5, 6), (4, 7)),
    ((0, 4), (1, 5), (2, 6), (3, 7)),
)


def foam(command: str, cwd: Path) -> subprocess.CompletedProcess:
    """One OpenFOAM command in ``cwd`` with its environment sourced."""
    return subprocess.run(
        ["bash", "-c", f"source {FOAM_RC} >/dev/null 2>&1; {command}"],
        cwd=cwd,
        capture_output=True,
        text=True,
    )


def parse(text: str) -> dict:
    """An expanded OpenFOAM dictionary as nested dicts and lists of string tokens."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    toks = re.findall(r"[(){};]|[^\s(){};]+", text)
    pos = 0

    def value():
        nonlocal pos
        tok = toks[pos]
        pos += 1
        if tok == "(":
            items = []
            while toks[pos] != ")":
                items.append(value())
            pos += 1
            return items
        if tok == "{":
            return entries("}")
        return tok

    def entries(end):
        nonlocal pos
        out = {}
        while pos < len(toks) and toks[pos] != end:
            key = toks[pos]
            pos += 1
            if toks[pos] == "{":
                out[key] = value()
                continue
            items = []
            while toks[pos] != ";":
                items.append(value())
            pos += 1
            out[key] = items[0] if len(items) == 1 else items
        pos += 1
        return out

    return entries(None)


def end_cells(grading, n: int) -> tuple[float, float, float, float]:
    """A blockMesh edge grading over n cells: its first, last and smallest cell as fractions
    of the edge's length, and the largest ratio of two neighbouring cells."""
    sections = [[float(v) for v in s] for s in grading] if isinstance(grading, list) else None
    if sections is None:
        sections = [[1.0, 1.0, float(grading)]]
    lengths = np.array([s[0] for s in sections])
    counts = np.array([s[1] for s in sections])
    lengths, counts = lengths / lengths.sum(), counts / counts.sum()
    cells = []
    for length, share, ratio in zip(lengths, counts, [s[2] for s in sections], strict=True):
        k = max(1, round(share * n))
        grow = ratio ** (1.0 / (k - 1)) if k > 1 else 1.0
        sizes = grow ** np.arange(k)
        cells.extend(length * sizes / sizes.sum())
    ratios = np.array(cells[1:]) / np.array(cells[:-1]) if n > 1 else np.ones(1)
    return cells[0], cells[-1], min(cells), float(max(ratios.max(), 1 / ratios.min()))


def arc_points(a: np.ndarray, mid: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Points along the circle through a, mid and b (2D), from a to b."""
    ax, ay = a
    bx, by = b
    cx, cy = mid
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    ux = (
        (ax**2 + ay**2) * (by - cy) + (bx**2 + by**2) * (cy - ay) + (cx**2 + cy**2) * (ay - by)
    ) / d
    uy = (
        (ax**2 + ay**2) * (cx - bx) + (bx**2 + by**2) * (ax - cx) + (cx**2 + cy**2) * (bx - ax)
    ) / d
    centre = np.array([ux, uy])
    t0, tm, t1 = (math.atan2(p[1] - uy, p[0] - ux) for p in (a, mid, b))
    sweep = (t1 - t0) % (2 * math.pi)
    if (tm - t0) % (2 * math.pi) > sweep:
        sweep -= 2 * math.pi
    k = max(2, math.ceil(abs(sweep) / ARC_STEP))
    ts = t0 + sweep * np.linspace(0.0, 1.0, k + 1)
    radius = np.linalg.norm(a - centre)
    pts = centre + radius * np.column_stack([np.cos(ts), np.sin(ts)])
    pts[0], pts[-1] = a, b
    return pts


class Section:
    """A blockMeshDict cut to its 2D section: points, quads, curves, counts, patches."""

    def __init__(self, d: dict) -> None:
        self.notes: list[str] = []
        scale = float(d.get("scale", d.get("convertToMeters", 1.0)))
        verts = np.array([[float(c) for c in v] for v in d["vertices"]]) * scale
        spread = [len(np.unique(np.round(verts[:, a], 9))) for a in range(3)]
        if 2 not in spread:
            raise ValueError("no axis with two vertex planes: not an extruded 2D blocking")
        self.axis = spread.index(2)
        keep = [a for a in range(3) if a != self.axis]
        flat = np.round(verts[:, keep], 9)
        self.points, self.vid = np.unique(flat, axis=0, return_inverse=True)
        self.vid = self.vid.ravel()
        self.quads, self.counts, self.fine = [], [], {}
        self.depth_cells, self.steepest = set(), 1.0
        self._blocks(d["blocks"], verts)
        if self.steepest > 1.0:
            self.notes.append(
                f"gradings whose cells grow up to {self.steepest:.3g} a cell left out "
                f"(SPEC 10: at most {MAX_GROWTH})"
            )
        self.curves = self._curves(d.get("edges", []), scale, keep)
        self.patches = self._patches(d)

    def _blocks(self, items: list, verts: np.ndarray) -> None:
        i = 0
        while i < len(items):
            assert items[i] == "hex", items[i]
            ids = [int(v) for v in items[i + 1]]
            i += 2
            if isinstance(items[i], str):  # a cell zone's name
                i += 1
            n = [int(v) for v in items[i]]
            kind, grading = items[i + 1], items[i + 2]
            i += 3
            normal = next(
                k
                for k in range(3)
                if all(self.vid[ids[p]] == self.vid[ids[q]] for p, q in HEX_EDGES[k])
            )
            self.depth_cells.add(n[normal])
            face = {2: (0, 1, 2, 3), 0: (0, 3, 7, 4), 1: (0, 1, 5, 4)}[normal]
            quad = [int(self.vid[ids[p]]) for p in face]
            if len(set(quad)) < 4:
                raise ValueError(f"block {len(self.quads)} is collapsed (a wedge or triangle)")
            dirs = [k for k in range(3) if k != normal]
            if normal == 0:  # face 0 3 7 4: its first direction is hex x2
                dirs = [1, 2]
            self.quads.append(quad)
            self.counts.append([n[k] for k in dirs])
            for j, k in enumerate(dirs):
                self._grading(quad, j, n[k], kind, grading, k, ids, verts)

    def _grading(self, quad, j, n, kind, grading, k, ids, verts) -> None:
        """The fine end cells of one block direction: --spacing candidates on its sides."""
        if kind == "simpleGrading":
            specs = [grading[k]] * 4
        else:
            specs = grading[4 * k : 4 * k + 4]
        firsts, lasts, lengths, smallest, steepest = [], [], [], [], 1.0
        for spec, (p, q) in zip(specs, HEX_EDGES[k], strict=True):
            length = float(np.linalg.norm(verts[ids[q]] - verts[ids[p]]))
            first, last, low, growth = end_cells(spec, n)
            steepest = max(steepest, growth)
            firsts.append(first * length)
            lasts.append(last * length)
            lengths.append(length)
            smallest.append((low, min(first, last)))
        q0, q1, q2, q3 = quad
        start, end = ((q0, q3), (q1, q2)) if j == 0 else ((q0, q1), (q3, q2))
        even = 1.0 / n
        for side, cells in ((start, firsts), (end, lasts)):
            h = float(np.mean(cells))
            if h >= FINE_CELL * even * float(np.mean(lengths)):
                continue
            if steepest > MAX_GROWTH:
                self.steepest = max(self.steepest, steepest)
            else:
                key = tuple(sorted(side))
                self.fine[key] = min(h, self.fine.get(key, h))
        if any(low < FINE_CELL * even and low < end_min * 0.999 for low, end_min in smallest):
            self.notes.append("grading clusters cells inside a block (not expressible)")

    def _curves(self, items: list, scale: float, keep: list[int]) -> dict:
        curves, i = {}, 0
        while i < len(items):
            kind, a, b = items[i], int(items[i + 1]), int(items[i + 2])
            arg = items[i + 3]
            i += 4
            pa, pb = self.points[self.vid[a]], self.points[self.vid[b]]
            key = (int(self.vid[a]), int(self.vid[b]))
            if kind == "arc":
                if isinstance(arg, str):  # arc a b origin (x y z): not in this reader
                    raise ValueError(f"arc {a} {b} {arg}: only arcs through a point are read")
                mid = scale * np.array([float(c) for c in arg])[keep]
                pts = arc_points(pa, mid, pb)
            else:
                inner = scale * np.array([[float(c) for c in p] for p in arg])[:, keep]
                pts = np.vstack([pa, inner, pb])
                if kind.lower() != "polyline":
                    self.notes.append(f"{kind} edges drawn as polylines through their points")
            curves.setdefault(tuple(sorted(key)), pts if key[0] < key[1] else pts[::-1])
        return curves

    def _patches(self, d: dict) -> dict:
        """{2D side: (name, type)} from the dict's boundary (or old patches) list."""
        named = []
        if "boundary" in d:
            items = d["boundary"]
            for name, body in zip(items[::2], items[1::2], strict=True):
                named.append((name, body.get("type", "patch"), body.get("faces", [])))
        for kind, name, faces in zip(*[iter(d.get("patches", []))] * 3, strict=True):
            named.append((name, kind, faces))
        out = {}
        for name, kind, faces in named:
            if kind == "empty":
                continue
            if kind not in PATCH_TYPES:
                self.notes.append(f"patch {name} of type {kind} written as a plain patch")
            for face in faces:
                ends = sorted({int(self.vid[int(v)]) for v in face})
                if len(ends) == 2:
                    out[tuple(ends)] = (name, PATCH_TYPES.get(kind, "patch"))
        return out

    def curve(self, side: tuple[int, int]) -> np.ndarray:
        """The points of a side from side[0] to side[1]."""
        key = tuple(sorted(side))
        pts = self.curves.get(key, self.points[list(key)])
        return pts if key == tuple(side) else pts[::-1]

    def sides(self) -> dict:
        """{side: [blocks]} over the quads' four sides."""
        use: dict = {}
        for b, q in enumerate(self.quads):
            for s in range(4):
                use.setdefault(tuple(sorted((q[s], q[(s + 1) % 4]))), []).append(b)
        return use

    def rings(self) -> list[np.ndarray]:
        """The boundary as closed rings of points (sides of one block only)."""
        bound = [s for s, bs in self.sides().items() if len(bs) == 1]
        nxt: dict = {}
        for a, b in bound:
            nxt.setdefault(a, []).append(b)
            nxt.setdefault(b, []).append(a)
        seen, rings = set(), []
        for start in nxt:
            if start in seen:
                continue
            ring, prev, cur = [], None, start
            while True:
                seen.add(cur)
                step = next(v for v in nxt[cur] if v != prev and (v not in seen or v == start))
                ring.append(self.curve((cur, step))[:-1])
                prev, cur = cur, step
                if cur == start:
                    break
            rings.append(np.vstack(ring))
        return sorted(rings, key=lambda r: -abs(_area(r)))

    def chains(self) -> list[tuple[tuple[int, int], int]]:
        """One (side, count) per chain of opposite sides: its longest side."""
        parent: dict = {}

        def find(s):
            while parent.setdefault(s, s) != s:
                s = parent[s]
            return s

        count: dict = {}
        for q, n in zip(self.quads, self.counts, strict=True):
            q0, q1, q2, q3 = q
            for (s, t), m in (
                (((q0, q1), (q3, q2)), n[0]),
                (((q0, q3), (q1, q2)), n[1]),
            ):
                s, t = tuple(sorted(s)), tuple(sorted(t))
                parent[find(s)] = find(t)
                count[s] = count[t] = m
        groups: dict = {}
        for s in count:
            groups.setdefault(find(s), []).append(s)
        return [
            (max(g, key=lambda s: _length(self.curve(s))), count[g[0]]) for g in groups.values()
        ]


def _area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _length(pts: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


def _midpoint(pts: np.ndarray) -> np.ndarray:
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    half = s[-1] / 2
    return np.array([np.interp(half, s, pts[:, 0]), np.interp(half, s, pts[:, 1])])


def _item(p: np.ndarray) -> str:
    return f"{p[0]:.9g},{p[1]:.9g}"


def write_inputs(sec: Section, folder: Path) -> list[str]:
    """The boundary and block-edge files and the options of one section."""
    import pyvista as pv

    def polydata(lines: list[np.ndarray], closed: bool) -> pv.PolyData:
        pts, cells, off = [], [], 0
        for line in lines:
            n = len(line)
            ids = list(range(off, off + n)) + ([off] if closed else [])
            cells += [len(ids), *ids]
            pts.append(np.column_stack([line, np.zeros(n)]))
            off += n
        return pv.PolyData(np.vstack(pts), lines=np.array(cells))

    folder.mkdir(parents=True, exist_ok=True)
    polydata(sec.rings(), True).save(folder / "boundary.vtp")
    inner = [sec.curve(s) for s, bs in sec.sides().items() if len(bs) == 2]
    args = [str(folder / "boundary.vtp")]
    if not inner:
        raise ValueError("one block: a four-sided domain, not a multi-block one")
    polydata(inner, False).save(folder / "edges.vtp")
    args += ["--blocks", str(folder / "edges.vtp")]
    for side, n in sec.chains():
        args.append(f"--cells={_item(_midpoint(sec.curve(side)))}={n}")
    for side, h in sec.fine.items():
        args.append(f"--spacing={_item(_midpoint(sec.curve(side)))}={h:.6g}")
    for side, (name, kind) in sec.patches.items():
        args.append(f"--patch={_item(_midpoint(sec.curve(side)))}={name}:{kind}")
    return args


def checkmesh(case: Path) -> tuple[int | None, float | None, str]:
    """checkMesh's cells, largest non-orthogonality and verdict on an OpenFOAM case."""
    log = foam("checkMesh", case).stdout
    cells = re.search(r"^\s*cells:\s+(\d+)", log, re.M)
    nonorth = re.search(r"Mesh non-orthogonality Max:\s*([\d.eE+-]+)", log)
    verdict = "OK" if "Mesh OK." in log else "failed"
    return (
        int(cells.group(1)) if cells else None,
        float(nonorth.group(1)) if nonorth else None,
        verdict,
    )


def run_case(folder: Path) -> list[dict]:
    """blockMesh and pinn-mesh (each method) on one case; a row per run."""
    name = folder.name
    work = OUT / name
    shutil.rmtree(work, ignore_errors=True)
    (work / "blockmesh" / "system").mkdir(parents=True)
    shutil.copy(folder / "blockMeshDict", work / "blockmesh" / "system" / "blockMeshDict")
    for rel, text in case_files("blockmesh").items():
        (work / "blockmesh" / rel).write_text(text)
    expanded = foam("foamDictionary -expand system/blockMeshDict", work / "blockmesh")
    if expanded.returncode:
        log = (expanded.stdout + expanded.stderr).split("FOAM FATAL", 1)[-1].splitlines()
        reason = next((line.strip() for line in log[1:] if line.strip()), "no message")
        return [{"case": name, "method": "-", "result": f"not read by foamDictionary: {reason}"}]
    try:
        sec = Section(parse(expanded.stdout))
        args = write_inputs(sec, work / "inputs")
    except (ValueError, KeyError, StopIteration, AssertionError) as err:
        return [{"case": name, "method": "-", "result": f"not converted: {err}"}]
    foam("blockMesh", work / "blockmesh")
    ref_cells, ref_nonorth, _ = checkmesh(work / "blockmesh")
    depth = max(sec.depth_cells)
    if ref_cells and depth > 1:
        ref_cells //= depth
        sec.notes.append(f"{depth} cells deep: the 2D section only")
    rows = []
    for method, options in METHODS.items():
        case = work / method.replace(" ", "_")
        report = work / f"{case.name}.json"
        cmd = [sys.executable, "-m", "pinn_engine.command", *args, *options]
        cmd += ["--format", "openfoam", "-o", str(case), "--report", str(report), "--quiet"]
        (work / f"{case.name}.cmd").write_text(" ".join(cmd) + "\n")
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_LIMIT)
        except subprocess.TimeoutExpired:
            rows.append({"case": name, "method": method, "result": "timed out"})
            continue
        row = {"case": name, "method": method, "blocks": len(sec.quads)}
        row["blockmesh_nonorth"], row["blockmesh_cells"] = ref_nonorth, ref_cells
        if proc.returncode:
            lines = (proc.stderr or proc.stdout).strip().splitlines() or ["no message"]
            row["result"] = "refused: " + lines[-1]
        else:
            q = json.loads(report.read_text())["quality"]
            cells, nonorth, verdict = checkmesh(case)
            row.update(result="accepted", folded=q["folded_cells"], cells=cells)
            row.update(mean=q["mean_max_angle"], worst=q["worst_max_angle"])
            row.update(nonorth=nonorth, checkmesh=verdict)
        row["notes"] = "; ".join(dict.fromkeys(sec.notes))
        rows.append(row)
    return rows


def table(rows: list[dict]) -> str:
    """The rows as a Markdown table."""

    def f(v, fmt="{:.2f}"):
        return "-" if v is None else fmt.format(v)

    out = [
        "| case | blocks | method | result | folded | mean / worst MaxIncludedAngle | "
        "max non-orth. ours / blockMesh | cells ours / blockMesh | notes |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        out.append(
            f"| {r['case']} | {r.get('blocks', '-')} | {r['method']} | {r['result']} | "
            f"{r.get('folded', '-')} | {f(r.get('mean'))} / {f(r.get('worst'))} | "
            f"{f(r.get('nonorth'))} / {f(r.get('blockmesh_nonorth'))} | "
            f"{r.get('cells', '-')} / {r.get('blockmesh_cells', '-')} | {r.get('notes', '')} |"
        )
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="a folder of cases, each with a blockMeshDict")
    parser.add_argument("--only", nargs="*", help="case names to run (default all)")
    args = parser.parse_args()
    rows = []
    for case in sorted(p.parent for p in args.folder.glob("*/blockMeshDict")):
        if args.only and case.name not in args.only:
            continue
        rows += run_case(case)
        print("\n".join(table(rows).splitlines()[-len(METHODS) :]), flush=True)
    print(table(rows))


if __name__ == "__main__":
    main()
