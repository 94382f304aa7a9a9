"""Gmsh mesh (``.msh``, format 4.1 ASCII), written by hand.

The format is plain text and fully documented, and a writer that needs only numpy also
works inside ParaView's Python, where the ``gmsh`` wheel (a 100 MB native library) is not
available; the tests read every file back with Gmsh's own API.

Entities are those of the logical box: its corners, edges, faces (and, extruded or
hexahedral, the volume); each node is classified on the entity it lies on. Elements:
quadrangles (2D) or hexahedra (extruded, or a hexahedral grid of SPEC 11) in the physical
group ``fluid``; per patch a physical curve (2D, lines with the domain on their left) or
surface (3D, quadrangles facing out), plus ``frontAndBack`` for the two ends of an
extrusion. Node tags are ``1 + i + ni * (j + nj * k)``.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.io.export import bodies
from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.multiblock import Blocks, merged
from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.export.text import write_rows
from pinn_engine.io.export.topology import (
    BOX_SIDES,
    box_faces,
    end_faces,
    hexahedra,
    quads,
    side_edges,
    side_faces,
)
from pinn_engine.patchnames import FRONT_AND_BACK

FLUID = "fluid"
# entity state of a side per axis (0: first index, 1: interior, 2: last index)
_SIDE_STATE = {"bottom": (1, 0), "right": (2, 1), "top": (1, 2), "left": (0, 1)}


def _states(n: int) -> np.ndarray:
    s = np.ones(n, dtype=int)
    s[0], s[-1] = 0, 2
    return s


def _boundary(state: tuple[int, ...]) -> list[tuple[tuple[int, ...], int]]:
    """The bounding entities of an entity and their signs (Gmsh's orientation rules)."""
    free = [a for a, s in enumerate(state) if s == 1]

    def at(axis, value):
        return tuple(value if a == axis else s for a, s in enumerate(state))

    if len(free) == 1:
        return [(at(free[0], 0), 1), (at(free[0], 2), -1)]
    if len(free) == 2:
        a, b = free
        return [(at(b, 0), 1), (at(a, 2), 1), (at(b, 2), -1), (at(a, 0), -1)]
    return [(at(a, v), 1) for a in free for v in (0, 2)]


def write_quadmesh(mesh: QuadMesh, path: Path) -> None:
    """An unstructured quad mesh (merged nodes), 2D: one discrete surface (physical
    ``fluid``) and one discrete curve per patch, all nodes on the surface."""
    write_unstructured(mesh.points, mesh.quads, mesh.patches, path, 2)


def write_unstructured(
    coords: np.ndarray, cells: np.ndarray, patches: dict[str, np.ndarray], path: Path, dim: int
) -> None:
    """An unstructured mesh (merged nodes) of quads (``dim`` 2) or hexahedra (3, VTK's
    node order): one discrete entity of dimension ``dim`` (physical ``fluid``) holding every
    node, and one of dimension ``dim - 1`` per patch, its elements the patch's lines or
    quads."""
    names = list(patches)
    fluid_tag = len(names) + 1
    lo, hi = coords.min(axis=0), coords.max(axis=0)
    box = " ".join(_num(v) for v in (*lo, *hi))
    counts = [0, 0, 0, 0]
    counts[dim - 1], counts[dim] = len(names), 1
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names) + 1)]
    lines += [f'{dim - 1} {k + 1} "{name}"' for k, name in enumerate(names)]
    lines += [f'{dim} {fluid_tag} "{FLUID}"', "$EndPhysicalNames", "$Entities"]
    lines.append(" ".join(map(str, counts)))
    for k, name in enumerate(names):
        pts = coords[np.unique(patches[name])]
        bb = " ".join(_num(v) for v in (*pts.min(axis=0), *pts.max(axis=0)))
        lines.append(f"{k + 1} {bb} 1 {k + 1} 0")
    lines += [
        f"1 {box} 1 {fluid_tag} 0",
        "$EndEntities",
        "$Nodes",
        f"1 {len(coords)} 1 {len(coords)}",
        f"{dim} 1 0 {len(coords)}",
    ]
    cell_kind, face_kind = (3, 1) if dim == 2 else (5, 3)  # Gmsh's quad, line; hexahedron, quad
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
        write_rows(f, np.arange(1, len(coords) + 1), "%d")
        write_rows(f, coords, "%.17g %.17g %.17g")
        f.write("$EndNodes\n")
        blocks = [(dim, 1, cell_kind, cells)]
        blocks += [(dim - 1, k + 1, face_kind, patches[n]) for k, n in enumerate(names)]
        total = sum(len(e) for *_, e in blocks)
        f.write(f"$Elements\n{len(blocks)} {total} 1 {total}\n")
        first = 1
        for d, tag, kind, elems in blocks:
            f.write(f"{d} {tag} {kind} {len(elems)}\n")
            rows = np.column_stack([np.arange(first, first + len(elems)), elems + 1])
            write_rows(f, rows, " ".join(["%d"] * rows.shape[1]))
            first += len(elems)
        f.write("$EndElements\n")


def write(block: Block, path: Path) -> None:
    if block.topology:  # seam or cut nodes merged (bodies.py)
        if block.thickness is not None:
            raise InputError(
                "an O- or C-grid is written to Gmsh in 2D in this build; drop {extrude}", str(path)
            )
        write_quadmesh(bodies.quad_mesh(block), path)
        return
    xyz = block.layers()
    nk, nj, ni = xyz.shape[:3]
    three_d = nk > 1
    faces: dict[str, list[tuple[tuple[int, ...], np.ndarray]]] = {}
    for name, sides in block.patches().items():
        for side in sides:
            state = _SIDE_STATE[side] + ((1,) if three_d else ())
            elems = side_faces(ni, nj, side) if three_d else side_edges(ni, nj, side)
            faces.setdefault(name, []).append((state, elems))
    if three_d:
        faces.setdefault(FRONT_AND_BACK, []).extend(
            [((1, 1, 0), end_faces(ni, nj, "back")), ((1, 1, 2), end_faces(ni, nj, "front"))]
        )
    _write_structured(xyz, faces, path)


def write_box(box: Box, path: Path) -> None:
    """A hexahedral grid (SPEC 11): hexahedra in ``fluid``, a physical surface per patch."""
    faces: dict[str, list[tuple[tuple[int, ...], np.ndarray]]] = {}
    for name, sides in box.patches().items():
        for side in sides:
            axis, end = divmod(BOX_SIDES.index(side), 2)
            state = tuple(2 * end if a == axis else 1 for a in range(3))
            faces.setdefault(name, []).append((state, box_faces(*box.shape, side)))
    _write_structured(box.xyz, faces, path)


def _write_structured(
    xyz: np.ndarray, faces: dict[str, list[tuple[tuple[int, ...], np.ndarray]]], path: Path
) -> None:
    """A structured grid ``xyz`` (nk, nj, ni, 3; nk = 1: 2D) with the boundary elements of
    each physical group ``faces`` (name -> [(entity state, elements)])."""
    nk, nj, ni = xyz.shape[:3]
    three_d = nk > 1
    shape = (ni, nj, nk) if three_d else (ni, nj)
    dim = len(shape)
    coords = xyz.reshape(-1, 3)
    # entity of every node, from the state of its index along each axis
    node_state = np.stack(np.meshgrid(*[_states(n) for n in shape], indexing="ij"), -1)
    node_state = node_state.transpose(*range(dim)[::-1], dim).reshape(-1, dim)  # i fastest
    entities = sorted(itertools.product((0, 1, 2), repeat=dim), key=lambda s: (s.count(1), s))
    tags: dict[tuple[int, ...], int] = {}
    for state in entities:
        d = state.count(1)
        tags[state] = 1 + sum(1 for other in tags if other.count(1) == d)

    # physical groups: one per patch (dimension dim - 1), fluid (dim)
    physical = {name: k + 1 for k, name in enumerate(faces)}
    fluid_tag = len(physical) + 1
    entity_physical: dict[tuple[int, ...], list[int]] = {(1,) * dim: [fluid_tag]}
    for name, parts in faces.items():
        for state, _ in parts:
            entity_physical.setdefault(state, []).append(physical[name])

    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(physical) + 1)]
    lines += [f'{dim - 1} {tag} "{name}"' for name, tag in physical.items()]
    lines += [f'{dim} {fluid_tag} "{FLUID}"', "$EndPhysicalNames", "$Entities"]
    counts = [sum(1 for s in entities if s.count(1) == d) for d in range(4)]
    lines.append(" ".join(map(str, counts)))
    for state in entities:
        inside = np.all((node_state == state) | (np.array(state) == 1), axis=1)
        pts = coords[inside]
        phys = entity_physical.get(state, [])
        head = [tags[state]] + (
            list(pts[0]) if state.count(1) == 0 else [*pts.min(axis=0), *pts.max(axis=0)]
        )
        row = [*map(_num, head), str(len(phys)), *map(str, phys)]
        if state.count(1):
            bound = _boundary(state)
            row += [str(len(bound))] + [str(sign * tags[s]) for s, sign in bound]
        lines.append(" ".join(row))
    lines.append("$EndEntities")

    blocks = []
    for state in entities:
        ids = np.flatnonzero(np.all(node_state == state, axis=1))
        if len(ids):
            blocks.append((state, ids))
    lines += ["$Nodes", f"{len(blocks)} {ni * nj * nk} 1 {ni * nj * nk}"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
        for state, ids in blocks:
            f.write(f"{state.count(1)} {tags[state]} 0 {len(ids)}\n")
            write_rows(f, ids + 1, "%d")
            write_rows(f, coords[ids], "%.17g %.17g %.17g")
        f.write("$EndNodes\n")
        volume = hexahedra(ni, nj, nk) if three_d else quads(ni, nj)
        element_blocks = [((1,) * dim, 5 if three_d else 3, volume)]
        boundary_type = 3 if three_d else 1
        for parts in faces.values():
            element_blocks += [(state, boundary_type, elems) for state, elems in parts]
        total = sum(len(e) for _, _, e in element_blocks)
        f.write(f"$Elements\n{len(element_blocks)} {total} 1 {total}\n")
        first = 1
        for state, kind, elems in element_blocks:
            f.write(f"{state.count(1)} {tags[state]} {kind} {len(elems)}\n")
            rows = np.column_stack([np.arange(first, first + len(elems)), elems + 1])
            write_rows(f, rows, " ".join(["%d"] * rows.shape[1]))
            first += len(elems)
        f.write("$EndElements\n")


def _num(x) -> str:
    return f"{float(x):.17g}" if not isinstance(x, int) else str(x)


def write_blocks(blocks: Blocks, path: Path, extrude: None) -> None:
    """A multi-block grid (SPEC 10), in 2D: one mesh, each shared node once."""
    write_quadmesh(merged(blocks), path)


register(
    Format(
        "msh",
        ".msh",
        "Gmsh 4.1 mesh with physical groups",
        True,
        name="Gmsh",
        block=write,
        box=write_box,
        blocks=write_blocks,
        paraview=("msh", "PINNMeshGmshWriter", "PINN Mesh Gmsh"),
    )
)
