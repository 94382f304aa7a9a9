"""OpenFOAM case (``DIR/constant/polyMesh``), written by hand in OpenFOAM's ASCII format.

OpenFOAM meshes are always 3D: a 2D grid is extruded one cell in z (thickness T, by default
the grid's mean edge length) and the two ends form the patch ``frontAndBack`` of type
``empty``, OpenFOAM's 2D idiom; a hexahedral grid (SPEC 11) is written as it is. Faces
follow polyMesh's rules: internal faces first, in upper-triangular order (by owner, then
neighbour) with normals from owner to neighbour, then the boundary faces patch by patch
with normals out of the domain. A minimal ``system/`` (controlDict, fvSchemes, fvSolution)
makes the case readable by ``checkMesh`` and ParaView at once; existing files there are
kept.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pinn_engine.geometry.faces import FaceTopology, face_keys
from pinn_engine.io.export import bodies
from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.multiblock import Blocks, merged
from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.export.text import write_rows
from pinn_engine.io.export.topology import (
    box_cells,
    box_faces,
    end_faces,
    inner_faces,
    mean_edge,
    quads,
    side_cells,
    side_faces,
)
from pinn_engine.patchnames import FRONT_AND_BACK, TYPES

_HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    location    "{location}";
    object      {obj};
}}
"""
SYSTEM = {
    "controlDict": """application     simpleFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         1;
deltaT          1;
writeControl    timeStep;
writeInterval   1;
""",
    "fvSchemes": """ddtSchemes { default steadyState; }
gradSchemes { default Gauss linear; }
divSchemes { default none; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
""",
    "fvSolution": "solvers {}\n",
}


def _header(cls: str, obj: str, location: str = "constant/polyMesh") -> str:
    return _HEADER.format(cls=cls, location=location, obj=obj)


def _write_list(path: Path, cls: str, rows: np.ndarray, note: str = "") -> None:
    """An OpenFOAM list file: points (vectors), faces (point lists) or labels."""
    with open(path, "w") as f:
        f.write(_header(cls, path.name).replace("    object", f"{note}    object"))
        f.write(f"\n{len(rows)}\n(\n")
        fmt = {"vectorField": "(%.17g %.17g %.17g)", "faceList": "4(%d %d %d %d)"}
        write_rows(f, rows, fmt.get(cls, "%d"))
        f.write(")\n")


def internal_faces(ni: int, nj: int, nk: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Faces between the cells of an (ni, nj, nk) grid (nk = 2: a 2D grid's extrusion) in
    upper-triangular order (by owner, then neighbour), their owners and neighbours."""
    faces, owner, neighbour = inner_faces(ni, nj, nk)
    order = np.lexsort((neighbour, owner))
    return faces[order], owner[order], neighbour[order]


def write_polymesh(block: Block, mesh: Path) -> None:
    """Write the polyMesh files (points, faces, owner, neighbour, boundary) into ``mesh``."""
    ni, nj = block.ni, block.nj
    faces, owner, neighbour = internal_faces(ni, nj)
    patches: list[tuple[str, str, np.ndarray, np.ndarray]] = []
    for name, sides in block.patches().items():
        patches.append(
            (
                name,
                TYPES[block.patch_type(name)][0],
                np.vstack([side_faces(ni, nj, s) for s in sides]),
                np.concatenate([side_cells(ni, nj, s) for s in sides]),
            )
        )
    cells = np.arange(len(quads(ni, nj)))
    patches.append(
        (
            FRONT_AND_BACK,
            "empty",
            np.vstack([end_faces(ni, nj, "back"), end_faces(ni, nj, "front")]),
            np.concatenate([cells, cells]),
        )
    )
    write_mesh_files(mesh, block.layers().reshape(-1, 3), faces, owner, neighbour, patches)


def write_box_polymesh(box: Box, mesh: Path) -> None:
    """The polyMesh of a hexahedral grid (SPEC 11, no extrusion): a patch per name of its
    six sides, of the type given (``patchnames.TYPES``)."""
    ni, nj, nk = box.shape
    faces, owner, neighbour = internal_faces(ni, nj, nk)
    patches = [
        (
            name,
            TYPES[box.patch_type(name)][0],
            np.vstack([box_faces(ni, nj, nk, s) for s in sides]),
            np.concatenate([box_cells(ni, nj, nk, s) for s in sides]),
        )
        for name, sides in box.patches().items()
    ]
    write_mesh_files(mesh, box.xyz.reshape(-1, 3), faces, owner, neighbour, patches)


def write_quadmesh_polymesh(mesh: QuadMesh, thickness: float, folder: Path) -> None:
    """polyMesh of an unstructured quad mesh (merged nodes: an O- or C-grid, a multi-block
    grid) extruded one cell of ``thickness`` in z: faces between two quads are internal,
    each patch's edges become its faces, the two ends ``frontAndBack`` (empty)."""
    q = mesh.quads  # counter-clockwise seen from +z
    m = len(mesh.points)
    points = np.vstack([mesh.points, mesh.points + np.array([0.0, 0.0, abs(thickness)])])
    n_cells = len(q)
    a = q.ravel()
    b = np.roll(q, -1, axis=1).ravel()
    owner_of = np.repeat(np.arange(n_cells), 4)
    key = np.sort(np.column_stack([a, b]), axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    side = np.column_stack([a, b, b + m, a + m])  # normal out of the cell that owns the edge
    # internal faces: the lower cell owns the face, oriented as that cell's edge
    shared = counts[inverse] == 2
    order = np.lexsort((owner_of[shared], inverse[shared]))
    idx = np.flatnonzero(shared)[order].reshape(-1, 2)  # the two edge copies of each face
    first, second = idx[:, 0], idx[:, 1]
    swap = owner_of[first] > owner_of[second]
    own = np.where(swap, second, first)
    nei = np.where(swap, first, second)
    faces, owner, neighbour = side[own], owner_of[own], owner_of[nei]
    sort = np.lexsort((neighbour, owner))
    faces, owner, neighbour = faces[sort], owner[sort], neighbour[sort]
    # boundary faces, patch by patch
    single = np.flatnonzero(counts[inverse] == 1)
    lookup = {tuple(key[k]): k for k in single}
    patches = []
    for name, edges in mesh.patches.items():
        ks = np.array([lookup[tuple(sorted(e))] for e in edges])
        patches.append((name, TYPES[mesh.types[name]][0], side[ks], owner_of[ks]))
    ids = np.arange(n_cells)
    patches.append(
        (FRONT_AND_BACK, "empty", np.vstack([q[:, ::-1], q + m]), np.concatenate([ids, ids]))
    )
    write_mesh_files(folder, points, faces, owner, neighbour, patches)


def write_hex_polymesh(
    points: np.ndarray,
    faces: FaceTopology,
    patches: list[tuple[str, str, np.ndarray]],
    mesh: Path,
    entries: dict[str, dict[str, str]] | None = None,
) -> None:
    """The polyMesh of hexahedra over merged ``points`` from their faces (``faces``, each
    once as its owner sees it: ``geometry.faces.topology``, which checkMesh's figures use
    too): the internal faces in upper-triangular order, every other face in the patch
    (name, OpenFOAM type, its faces (k, 4) of point ids) listing it, with its normal out of
    its cell; ``entries``: a patch's further boundary entries by name (a cyclic's
    ``neighbourPatch``). A boundary face no patch lists is a programming error."""
    internal = len(faces.neighbour)
    sort = np.lexsort((faces.neighbour, faces.owner[:internal]))
    boundary, outside = faces.quads[internal:], faces.owner[internal:]
    found = _listed(boundary, [pf for _, _, pf in patches])
    out, start = [], 0
    for name, kind, pf in patches:
        mine = found[start : start + len(pf)]
        out.append((name, kind, boundary[mine], outside[mine]))
        start += len(pf)
    write_mesh_files(
        mesh,
        points,
        np.take(faces.quads, sort, axis=0),  # rows several times faster than [sort]
        faces.owner[sort],
        faces.neighbour[sort],
        out,
        entries,
    )


def _listed(boundary: np.ndarray, listed: list[np.ndarray]) -> np.ndarray:
    """Which of the ``boundary`` faces (k, 4) each face of the patches' lists (``listed``,
    (k, 4) point ids each, in any corner order) is, in the lists' order: the lists' faces
    and the boundary's sorted together by their keys, each listed face right after its
    boundary face. A boundary face no list has, or a listed face that is no boundary face
    or is listed twice, is a programming error."""
    if not listed:
        listed = [np.empty((0, 4), dtype=boundary.dtype)]
    low, high = face_keys(np.vstack([boundary, *listed]))
    at = np.lexsort((np.arange(len(low)), high, low))  # a boundary face before its listing
    same = (low[at][1:] == low[at][:-1]) & (high[at][1:] == high[at][:-1])
    is_listed = at >= len(boundary)
    ok = same & is_listed[1:] & ~is_listed[:-1]
    found = np.full(len(low) - len(boundary), -1)
    found[at[1:][ok] - len(boundary)] = at[:-1][ok]
    if (found < 0).any():
        raise ValueError(f"{int((found < 0).sum())} patch faces are no boundary face")
    if len(boundary) > ok.sum():
        raise ValueError(f"{len(boundary) - int(ok.sum())} boundary faces are in no patch")
    return found


def write_mesh_files(
    mesh: Path,
    points: np.ndarray,
    faces: np.ndarray,
    owner: np.ndarray,
    neighbour: np.ndarray,
    patches: list,
    entries: dict[str, dict[str, str]] | None = None,
) -> None:
    """The five polyMesh files from the points, the internal faces (owner-ordered) and the
    patches as (name, type, faces, owner cells), in ``mesh``; ``entries``: further
    entries of a patch's boundary dictionary, by patch name."""
    all_faces = np.vstack([faces] + [p[2] for p in patches])
    all_owner = np.concatenate([owner] + [p[3] for p in patches])
    n_cells = int(max(owner.max(initial=-1), all_owner.max(initial=-1))) + 1
    note = (
        f'    note        "nPoints:{len(points)} nCells:{n_cells} nFaces:{len(all_faces)} '
        f'nInternalFaces:{len(faces)}";\n'
    )
    _write_list(mesh / "points", "vectorField", points)
    _write_list(mesh / "faces", "faceList", all_faces)
    _write_list(mesh / "owner", "labelList", all_owner, note)
    _write_list(mesh / "neighbour", "labelList", neighbour, note)
    text = [_header("polyBoundaryMesh", "boundary"), f"\n{len(patches)}\n(\n"]
    start = len(faces)
    for name, kind, pf, _ in patches:
        group = "        inGroups        List<word> 1(empty);\n" if kind == "empty" else ""
        group += "".join(
            f"        {key:<16}{value};\n" for key, value in (entries or {}).get(name, {}).items()
        )
        text.append(
            f"    {name}\n    {{\n        type            {kind};\n{group}"
            f"        nFaces          {len(pf)};\n        startFace       {start};\n"
            "    }\n"
        )
        start += len(pf)
    text.append(")\n")
    (mesh / "boundary").write_text("".join(text))


def case_files(title: str) -> dict[str, str]:
    """The files besides the polyMesh (relative path -> text): a minimal ``system/`` and the
    empty ``<title>.foam`` that ParaView opens."""
    files = {
        f"system/{name}": _header("dictionary", name, "system") + "\n" + body
        for name, body in SYSTEM.items()
    }
    files[f"{title}.foam"] = ""
    return files


def write_block(block: Block, folder: Path) -> None:
    """A 2D grid extruded one cell in z; an O- or C-grid with its seam or cut merged."""
    if block.topology:
        write_quadmesh_polymesh(bodies.quad_mesh(block), block.thickness, folder)
    else:
        write_polymesh(block, folder)


def write_blocks(blocks: Blocks, folder: Path, extrude: float | None) -> None:
    """A multi-block grid (SPEC 10), one cell in z (``extrude``, else the blocks' mean edge
    length): one mesh, each shared node once."""
    thickness = extrude or float(np.mean([mean_edge(p) for p in blocks.points]))
    write_quadmesh_polymesh(merged(blocks), thickness, folder)


register(
    Format(
        "openfoam",
        "",
        "OpenFOAM case (constant/polyMesh)",
        True,
        name="OpenFOAM",
        block=write_block,
        box=write_box_polymesh,
        blocks=write_blocks,
        blocks_extrude=True,
        solid=True,
        paraview=("foam", "PINNMeshOpenFOAMWriter", "PINN Mesh OpenFOAM"),
    )
)
