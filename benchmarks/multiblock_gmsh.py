"""Multi-block grids against gmsh (SPEC 10): the same blocks with the same drawn
nodes meshed by gmsh's transfinite surfaces, beside pinn-mesh's grids.

Usage: ``.venv/bin/python benchmarks/multiblock_gmsh.py [--out docs/multiblock.md]
[--smoothing N]`` (gmsh comes with the test extra: ``pip install -e .[test]``)

Per example of ``benchmarks/multiblock.py`` (at its cell size there) pinn-mesh's topology
and node layout (``pinn_engine.multiblock``: linework, blocks, cell counts, layout) give
every node on the boundary and on the drawn block edges. gmsh gets one point per such node,
one straight line per pair of consecutive nodes along each piece (transfinite with its two
end nodes only), and one transfinite surface per block (its four corners given),
recombined into quads: the same cells and the same nodes on every block side, where gmsh
keeps them (it cannot move an interface). gmsh meshes it twice: its transfinite
interpolation alone, and with its smoother on the transfinite surfaces (``setSmoothing``:
N Gauss-Seidel sweeps of the Winslow equations in each block, its sides fixed; N = 100,
the figure of gmsh's tutorial t6, or ``--smoothing N``). Each block's
nodes are read back into pinn-mesh's (nj, ni) orientation (side nodes by position, every
one of gmsh's boundary nodes checked to be one of ours, the interior by walking gmsh's
quads from the bottom side) and measured by pinn-mesh's own code: folded cells, mean /
worst MaxIncludedAngle, interface kink mean / max. Beside them pinn-mesh's ``tfi`` and
``elliptic`` with ``--interfaces fixed`` (the same drawn nodes), ``elliptic`` and the
default ``pinn`` (interfaces solved). Times: gmsh's ``generate`` alone (not building its
model); pinn-mesh's meshing as ``benchmarks/multiblock.py`` times it (files read, topology,
layout and solve). With ``--out`` the table replaces the part of that file between the
two GMSH markers.
"""

from __future__ import annotations

import argparse
import time
from collections import defaultdict
from pathlib import Path

import gmsh
import numpy as np
import torch
from multiblock import DATA, EXAMPLES, angles, run, write_between
from scipy.spatial import cKDTree

from pinn_engine.io.fileio import read_aux_lines, read_rings
from pinn_engine.multiblock.blocks import Topology, topology
from pinn_engine.multiblock.counts import cell_counts, default_cell_size
from pinn_engine.multiblock.elliptic import crossings
from pinn_engine.multiblock.graph import linework
from pinn_engine.multiblock.layout import Layout
from pinn_engine.multiblock.mesh import interface_kinks, layout_checked

SMOOTHING = 100  # sweeps: the figure of gmsh's tutorial t6 (its Mesh.Smoothing = 100 gives 99)
MATCH = 1e-9  # a gmsh node is one of ours within this share of the diagonal (gmsh copies them)
FIXED = "elliptic, fixed"  # pinn-mesh's converged Winslow on the drawn nodes: distances from it
OURS = (  # pinn-mesh's rows: label, method, more settings, its block-edge nodes
    ("tfi", "tfi", {}, "drawn"),
    (FIXED, "elliptic", {"interfaces": "fixed"}, "drawn"),
    ("elliptic", "elliptic", {}, "solved"),
    ("pinn (default)", "pinn", {}, "solved"),
)
GMSH = {"gmsh transfinite": 0, "gmsh smoothed": None}  # gmsh's rows: sweeps (None: --smoothing)
# the rows of an example: the drawn-node grids first, each gmsh grid after pinn-mesh's like it
ORDER = ("tfi", "gmsh transfinite", FIXED, "gmsh smoothed", "elliptic", "pinn (default)")
MARK = "<!-- GMSH {} -->"  # the markers round the table in --out


def drawn(stem: str, h: float) -> tuple[Topology, Layout]:
    """pinn-mesh's blocks and node layout of an example, as ``mesh_blocks`` makes them."""
    source = DATA / f"{stem}.vtp"
    edges = read_aux_lines(DATA / f"{stem}_blocks.vtp")
    lines = linework(read_rings(source), [e.points for e in edges], [e.name for e in edges], "")
    topo = topology(lines)
    h = h or default_cell_size(lines.diagonal)
    return topo, layout_checked(topo, cell_counts(topo, h), h)


def _ring(ids: np.ndarray) -> np.ndarray:
    """A block's side nodes counter-clockwise from corner 0, corner 0 again at the end."""
    return np.concatenate([ids[0], ids[1:, -1], ids[-1, -2::-1], ids[-2::-1, 0]])


def gmsh_model(lay: Layout, smoothing: int) -> None:
    """gmsh's model of the blocks: a point per drawn node (tag: our id + 1), a line per
    pair of neighbours on a piece, a transfinite quad surface per block (tag: block + 1)."""
    gmsh.model.add("blocks")
    geo = gmsh.model.geo
    for n in np.unique(np.concatenate(lay.piece_ids)):
        geo.addPoint(*lay.points[n], 0.0, tag=int(n) + 1)
    lines = {}
    for ids in lay.piece_ids:
        for a, b in zip(ids[:-1], ids[1:]):
            lines[(a, b)] = geo.addLine(int(a) + 1, int(b) + 1)
            geo.mesh.setTransfiniteCurve(lines[(a, b)], 2)
    for k, ids in enumerate(lay.ids):
        ring = _ring(ids)
        loop = [lines.get((a, b)) or -lines[(b, a)] for a, b in zip(ring[:-1], ring[1:])]
        surface = geo.addPlaneSurface([geo.addCurveLoop(loop)], tag=k + 1)
        corners = [ids[0, 0], ids[0, -1], ids[-1, -1], ids[-1, 0]]
        geo.mesh.setTransfiniteSurface(surface, cornerTags=[int(c) + 1 for c in corners])
        geo.mesh.setRecombine(2, surface)
        geo.mesh.setSmoothing(2, surface, smoothing)
    geo.synchronize()


def _walk(ids: np.ndarray, ours: dict[int, int], quads: np.ndarray) -> np.ndarray:
    """gmsh's node tags of a block in our (nj, ni) layout: the bottom side's from ``ours``
    (our id: gmsh tag), then row by row through the quads above; the other three sides
    checked to be ours."""
    over = defaultdict(list)  # directed edge (a, b): the nodes beyond a and b in each quad
    for q in quads:
        for k in range(4):
            a, b, c, d = np.roll(q, -k)
            over[(a, b)].append((d, c))
            over[(b, a)].append((c, d))
    tags = np.empty(ids.shape, dtype=np.int64)
    tags[0] = [ours[n] for n in ids[0]]
    for j in range(1, ids.shape[0]):
        for i in range(ids.shape[1] - 1):
            beyond = over[(tags[j - 1, i], tags[j - 1, i + 1])]  # one quad or two
            [(tags[j, i], tags[j, i + 1])] = [p for p in beyond if j < 2 or p[0] != tags[j - 2, i]]
    sides = np.concatenate([tags[-1], tags[:, 0], tags[:, -1]])
    wanted = [ours[n] for n in np.concatenate([ids[-1], ids[:, 0], ids[:, -1]])]
    assert np.array_equal(sides, wanted), "gmsh's block sides are not ours"
    return tags


def gmsh_grids(lay: Layout, diagonal: float, smoothing: int) -> tuple[list[np.ndarray], float]:
    """Each block's gmsh grid (nj, ni, 2) in our orientation, and gmsh's meshing time."""
    gmsh_model(lay, smoothing)
    start = time.perf_counter()
    gmsh.model.mesh.generate(2)
    seconds = time.perf_counter() - start
    drawn_nodes = np.unique(np.concatenate(lay.piece_ids))
    on = [gmsh.model.mesh.getNodes(dim)[:2] for dim in (0, 1)]  # on points and on lines
    tags, xyz = (np.concatenate(a) for a in zip(*on))
    gap, near = cKDTree(lay.points[drawn_nodes]).query(xyz.reshape(-1, 3)[:, :2])
    assert gap.max() <= MATCH * diagonal, "a gmsh side node is none of ours"
    ours = dict(zip(drawn_nodes[near].tolist(), tags.tolist()))  # our id: gmsh's tag
    assert len(ours) == len(tags) == len(drawn_nodes), "gmsh's side nodes are not ours"
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    assert len(tags) == len(lay.points), "gmsh's node count is not ours"
    xy = np.zeros((int(tags.max()) + 1, 2))
    xy[tags] = xyz.reshape(-1, 3)[:, :2]
    grids = []
    for k, ids in enumerate(lay.ids):
        _, _, nodes = gmsh.model.mesh.getElements(2, k + 1)
        grids.append(xy[_walk(ids, ours, nodes[0].reshape(-1, 4).astype(np.int64))])
    gmsh.model.remove()
    return grids, seconds


def _figures(topo: Topology, lay: Layout, grids: list[np.ndarray]) -> tuple:
    """Mean and worst MaxIncludedAngle, folded cells and the interface kinks of a grid."""
    points = lay.points.copy()
    for ids, grid in zip(lay.ids, grids):
        points[ids] = grid
    return *angles(grids), interface_kinks(crossings(topo, lay), lay, points)


def rows(smoothing: int) -> list[str]:
    """The table's rows: per example, pinn-mesh's grids and gmsh's in ORDER."""
    out = []
    for name, (stem, h) in EXAMPLES.items():
        topo, lay = drawn(stem, h)
        meshes = {}  # label: grids, seconds, block-edge nodes
        for label, method, overrides, edges in OURS:
            result, seconds = run(stem, method, h, **overrides)
            meshes[label] = result.grids, seconds, edges
        for label, sweeps in GMSH.items():
            sweeps = smoothing if sweeps is None else sweeps
            meshes[label] = (*gmsh_grids(lay, topo.lines.diagonal, sweeps), "drawn")
        report = result.report
        fixed = meshes[FIXED][0]
        first = f"| {name} ({report['cell_size']:.3g}) | {report['blocks']} | {report['cells']} "
        for k, label in enumerate(ORDER):
            grids, seconds, edges = meshes[label]
            mean, worst, folds, kinks = _figures(topo, lay, grids)
            far = max(np.linalg.norm(g - f, axis=2).max() for g, f in zip(grids, fixed))
            out.append(
                f"{first if k == 0 else '| | | '}| {label} | {edges} | {folds} | "
                f"{kinks.mean():.2f} / {kinks.max():.2f} | {mean:.2f} / {worst:.2f} | "
                f"{far / topo.lines.diagonal:.1e} | {seconds:.3f} s |"
            )
    return out


def markdown(smoothing: int) -> str:
    lines = [
        f"gmsh smoothed: {smoothing} sweeps of its smoother on each transfinite surface.",
        "",
        "| example (cell size) | blocks | cells | grid | block-edge nodes | folds | interface "
        "kink mean / max (deg) | mean / worst MaxIncludedAngle | farthest node from "
        f"{FIXED} (of the diagonal) | time |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows(smoothing),
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the two GMSH markers")
    parser.add_argument("--smoothing", type=int, default=SMOOTHING, help="gmsh's sweeps")
    args = parser.parse_args()
    torch.set_num_threads(1)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    text = markdown(args.smoothing)
    gmsh.finalize()
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    main()
