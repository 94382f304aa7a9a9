"""A blockMeshDict meshed (SPEC 15): blockMesh's placement, the Winslow grid over all blocks
and the choice between them, on each route; cells and patches as blockMesh's (where
OpenFOAM is installed), no fold, checkMesh's figures no worse."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from helpers import EXAMPLES, foam_env

from pinn_engine import job
from pinn_engine.blocks3d.checks import figures, hexes
from pinn_engine.blocks3d.dictionary import from_text
from pinn_engine.blocks3d.mesh import mesh_dictionary
from pinn_engine.blocks3d.placement import place
from pinn_engine.routes.cli import main
from pinn_engine.routes.summary_lines import dictionary_line
from pinn_engine.settings import make_settings

PIPE = EXAMPLES / "blockmesh" / "pipe" / "system" / "blockMeshDict"
needs_openfoam = pytest.mark.skipif(
    shutil.which("blockMesh") is None or shutil.which("checkMesh") is None,
    reason="OpenFOAM's blockMesh is missing (apt-get install openfoam; .ci/run installs it)",
)


def small_pipe() -> str:
    """The example pipe's dictionary with few cells (fast)."""
    text = PIPE.read_text()
    return text.replace("(12 12 40)", "(6 6 3)").replace("(12 10 40)", "(6 5 3)")


BOX = """
vertices ( (0 0 0) (2 0 0) (2 1 0) (0 1 0) (0 0 0.5) (2 0 0.5) (2 1 0.5) (0 1 0.5)
           (3 0 0) (3 1 0) (3 0 0.5) (3 1 0.5) );
blocks ( hex (0 1 2 3 4 5 6 7) (8 4 2) simpleGrading (3 0.5 1)
         hex (1 8 9 2 5 10 11 6) (4 4 2) simpleGrading (1 0.5 1) );
boundary ( walls { type wall; faces ((0 1 5 4) (1 8 10 5)); } );
"""


def test_a_graded_box_keeps_blockmesh_grid():
    """Straight edges, simpleGrading: blockMesh's grid is orthogonal, and the Winslow grid
    over both blocks in the dictionary's graded coordinates is that grid."""
    d = from_text(BOX)
    placed = place(d)
    x = np.unique(np.round(placed.points[:, 0], 12))
    cells = np.diff(x)
    assert len(x) == 13 and cells[7] / cells[0] == pytest.approx(3.0)
    result = mesh_dictionary(d, "elliptic")
    assert np.allclose(result.points, placed.points, atol=1e-9)
    assert [p[0] for p in placed.patches] == ["walls", "defaultFaces"]
    assert result.place.patches[1][1] == "empty"


def test_the_pipe_interfaces_are_solved():
    """The butterfly pipe: the Winslow grid, its centre square's corners moving as star
    nodes, is far less non-orthogonal than blockMesh's, with no fold; the wall stays on the
    cylinder and the inlet in its plane."""
    d = from_text(small_pipe())
    result = mesh_dictionary(d, "elliptic")
    tfi, ell = result.candidates["tfi"], result.candidates["elliptic"]
    assert result.kept == "elliptic" and ell.folded == 0
    assert ell.max_non_orthogonality < tfi.max_non_orthogonality - 5
    assert ell.max_skewness <= tfi.max_skewness
    wall = np.unique(result.place.patches[2][2])
    assert np.allclose(np.hypot(*result.points[wall, :2].T), 0.05)
    inlet = np.unique(result.place.patches[0][2])
    assert np.allclose(result.points[inlet, 2], 0.0)
    fixed = mesh_dictionary(d, "elliptic", free_interfaces=False)
    for ids in fixed.place.ids:  # block faces where blockMesh puts them
        for face in (ids[0], ids[-1], ids[:, 0], ids[:, -1], ids[:, :, 0], ids[:, :, -1]):
            assert np.allclose(fixed.points[face], fixed.place.points[face])


def bulging_pipe() -> str:
    """A butterfly pipe (radius 0.5, length 2) whose centre square's edges are arcs bulging
    out, cells graded 5:1 towards the wall: the Winslow grid is less non-orthogonal than
    blockMesh's but more skewed, so neither meets every aim."""
    c, s, b = 0.5 / np.sqrt(2), 0.25, 0.3125
    ring = [(-s, -s), (s, -s), (s, s), (-s, s), (-c, -c), (c, -c), (c, c), (-c, c)]
    vertices = " ".join(f"({x:.10g} {y:.10g} {z})" for z in (0, 2) for x, y in ring)
    quads = [(0, 1, 2, 3), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]
    blocks = " ".join(
        f"hex ({' '.join(str(v) for v in (*q, *(v + 8 for v in q)))}) "
        + ("(8 8 2) simpleGrading (1 1 1)" if k == 0 else "(6 8 2) simpleGrading (0.2 1 1)")
        for k, q in enumerate(quads)
    )
    mids = [(0, -1), (1, 0), (0, 1), (-1, 0)]
    edges = " ".join(
        f"arc {p + off} {q + off} ({r * mx:.10g} {r * my:.10g} {z})"
        for z, off in ((0, 0), (2, 8))
        for r, first in ((0.5, 4), (b, 0))
        for (mx, my), (p, q) in zip(mids, [(first + k, first + (k + 1) % 4) for k in range(4)])
    )
    return (
        f"vertices ( {vertices} ); blocks ( {blocks} ); edges ( {edges} );\n"
        "boundary ( wall { type wall; faces ( (4 5 13 12) (5 6 14 13) (6 7 15 14) "
        "(7 4 12 15) ); } );"
    )


def test_the_default_blends_towards_the_winslow_grid_as_far_as_the_aims_allow():
    """Where the Winslow grid is more skewed than blockMesh's, the default keeps the grid
    between them nearest the Winslow grid that is no more skewed, and far less
    non-orthogonal than blockMesh's; no fold, the wall on the cylinder."""
    result = mesh_dictionary(from_text(bulging_pipe()))
    tfi, ell = result.candidates["tfi"], result.candidates["elliptic"]
    assert ell.max_skewness > tfi.max_skewness  # the Winslow grid alone is not kept
    blend = result.candidates["blend"]
    assert result.blend == pytest.approx(0.53, abs=0.01)
    assert blend.max_skewness <= tfi.max_skewness and blend.folded == 0
    assert blend.max_non_orthogonality < tfi.max_non_orthogonality - 10
    kept = figures(result.points, result.cells)  # the section optimised from blend or tfi
    assert result.kept == "optimised"  # its figures measured on the slab, to round-off
    assert kept.as_dict() == pytest.approx(result.candidates["optimised"].as_dict(), abs=1e-9)
    assert result.report["start"] in ("blend", "tfi")
    assert kept.max_skewness <= blend.max_skewness and kept.folded == 0
    assert kept.max_non_orthogonality < blend.max_non_orthogonality - 10
    wall = np.unique(result.place.patches[0][2])
    assert np.allclose(np.hypot(*result.points[wall, :2].T), 0.5)
    line = dictionary_line({**result.report, "start": "blend"})
    assert "section-optimised blend (0.53 of the way" in line


def test_the_default_keeps_blockmesh_placement_where_it_is_better():
    """A grid the Winslow solve cannot improve on (orthogonal already) keeps blockMesh's
    placement, so no figure is ever worse than blockMesh's."""
    d = from_text(small_pipe())
    result = mesh_dictionary(d, "tfi")
    assert result.kept == "tfi" and "elliptic" not in result.candidates
    assert figures(result.points, result.cells) == result.candidates["tfi"]


def test_the_default_keeps_an_orthogonal_placement_unsolved():
    """blockMesh's grid within ``ORTHOGONAL`` of orthogonal everywhere (a graded box) is
    kept by the default with no solve; ``elliptic`` still solves it."""
    d = from_text(BOX)
    result = mesh_dictionary(d)
    assert result.kept == "tfi" and "elliptic" not in result.candidates
    assert result.report["unsolved"] and result.report["winslow_steps"] == 0
    assert "elliptic" in mesh_dictionary(d, "elliptic").candidates
    assert "unsolved" not in mesh_dictionary(from_text(small_pipe())).report


def test_the_job_gives_blocks_with_spec11_arrays():
    outcome = job.run(make_settings("pinn"), job.dictionary_from_text(small_pipe()))
    assert outcome.kind == "dictionary" and outcome.data.GetNumberOfBlocks() == 5
    grid = outcome.data.GetBlock(1)
    assert grid.GetExtent() == (0, 6, 0, 5, 0, 3)
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert grid.GetCellData().GetArray(name) is not None
    assert outcome.report["training"]["skipped"]
    assert outcome.grids[1].shape == (4, 6, 7, 3)


def test_the_command_line_writes_vtm(tmp_path):
    dict_path = tmp_path / "pipe" / "system" / "blockMeshDict"
    dict_path.parent.mkdir(parents=True)
    dict_path.write_text(small_pipe())
    out = tmp_path / "pipe.vtm"
    assert main([str(dict_path), "-o", str(out), "--quiet"]) == 0
    assert len(list((tmp_path / "pipe").glob("block*.vts"))) == 5
    assert main([str(dict_path), "-o", str(tmp_path / "x.xyz"), "--quiet"]) == 2


def test_su2_and_gmsh_hold_the_merged_hexahedra_and_the_patches(tmp_path):
    """``-o OUT.su2`` / ``OUT.msh``: every cell once as a hexahedron of positive volume over
    the merged nodes, a marker (physical surface) per patch with its faces facing out."""
    dict_path = tmp_path / "pipe" / "system" / "blockMeshDict"
    dict_path.parent.mkdir(parents=True)
    dict_path.write_text(small_pipe())
    result = mesh_dictionary(from_text(small_pipe()))
    faces = {name: len(f) for name, _, f in result.place.patches}
    out = tmp_path / "pipe.su2"
    assert main([str(dict_path), "-o", str(out), "--quiet"]) == 0
    lines = out.read_text().splitlines()
    at = {line.split("=")[0]: k for k, line in enumerate(lines) if "=" in line}
    n_cells = int(lines[at["NELEM"]].split()[1])
    cells = np.array([[int(v) for v in lines[at["NELEM"] + 1 + k].split()[1:9]]
                      for k in range(n_cells)])  # fmt: skip
    n_points = int(lines[at["NPOIN"]].split()[1])
    points = np.array([[float(v) for v in lines[at["NPOIN"] + 1 + k].split()[:3]]
                       for k in range(n_points)])  # fmt: skip
    assert n_cells == len(result.cells) and n_points == len(result.points)
    assert figures(points, cells).folded == 0
    markers = re.findall(r"MARKER_TAG= (\w+)\nMARKER_ELEMS= (\d+)", out.read_text())
    assert {name: int(n) for name, n in markers} == faces
    centre = points.mean(axis=0)
    start = next(k for k, line in enumerate(lines) if line.startswith("MARKER_TAG= wall"))
    quads = np.array([[int(v) for v in lines[start + 2 + k].split()[1:]]
                      for k in range(faces["wall"])])  # fmt: skip
    p = points[quads]
    normal = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    outward = np.einsum("nk,nk->n", normal[:, :2], p.mean(axis=1)[:, :2] - centre[:2])
    assert (outward > 0).all()  # the pipe's wall faces point away from its axis
    gmsh = pytest.importorskip("gmsh")
    msh = tmp_path / "pipe.msh"
    assert main([str(dict_path), "-o", str(msh), "--quiet"]) == 0
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(msh))
        groups = {
            gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()
        }
        assert set(groups) == {*faces, "fluid"}
        kinds, tags, _ = gmsh.model.mesh.getElements(3)
        assert list(kinds) == [5] and len(tags[0]) == n_cells
        for name, count in faces.items():
            entity = gmsh.model.getEntitiesForPhysicalGroup(*groups[name])[0]
            assert len(gmsh.model.mesh.getElements(2, entity)[1][0]) == count
    finally:
        gmsh.finalize()


@needs_openfoam
def test_cells_and_patches_are_blockmesh_and_checkmesh_passes(tmp_path):
    """blockMesh and ``pinn-mesh DICT --format openfoam`` on the same dictionary: the same
    cells and patches; checkMesh passes ours, with no larger non-orthogonality."""
    env = foam_env()
    ref = tmp_path / "ref"
    (ref / "system").mkdir(parents=True)
    (ref / "system" / "blockMeshDict").write_text(small_pipe())
    ours = tmp_path / "ours"
    assert (
        main(
            [
                str(ref / "system" / "blockMeshDict"),
                "-o",
                str(ours),
                "--format",
                "openfoam",
                "--quiet",
            ]
        )
        == 0
    )
    for name in ("controlDict", "fvSchemes", "fvSolution"):
        shutil.copy(ours / "system" / name, ref / "system" / name)
    subprocess.run(["blockMesh"], cwd=ref, env=env, capture_output=True, check=True)

    def check(case):
        log = subprocess.run(
            ["checkMesh"], cwd=case, env=env, capture_output=True, text=True
        ).stdout
        cells = int(re.search(r"^\s*cells:\s+(\d+)", log, re.M).group(1))
        nonorth = float(re.search(r"non-orthogonality Max:\s*([\d.eE+-]+)", log).group(1))
        return cells, nonorth, "Mesh OK." in log

    def patches(case):
        text = (case / "constant" / "polyMesh" / "boundary").read_text()
        found = re.findall(r"(\w+)\s*\{\s*type\s+(\w+);.*?nFaces\s+(\d+);", text, re.S)
        return sorted(found)

    (cells, nonorth, ok), (ref_cells, ref_nonorth, _) = check(ours), check(ref)
    assert ok and cells == ref_cells and nonorth < ref_nonorth
    assert patches(ours) == patches(ref)
    assert sum(len(hexes(ids)) for ids in place(from_text(small_pipe())).ids) == cells


def test_a_listed_default_patch_takes_the_rest_and_empty_patches_stay():
    """As blockMesh: faces no patch lists go to the listed patch of the default's name, of
    its type; a listed patch without faces is kept (zero faces)."""
    text = BOX.replace(
        "boundary (",
        "boundary ( spare { type patch; faces (); } defaultFaces { type wall; faces (); }",
    )
    patches = place(from_text(text)).patches
    assert [(n, k, len(f)) for n, k, f in patches] == [
        ("spare", "patch", 0),
        ("defaultFaces", "wall", 2 * 4 * 2 + 12 * 2 + 2 * 12 * 4),  # ends, y = 1, z faces
        ("walls", "wall", 8 * 2 + 4 * 2),
    ]


def test_pyvista_reads_a_dictionary_as_blocks(tmp_path):
    import pinn_engine
    from pinn_engine.errors import SettingsError

    dict_path = tmp_path / "system" / "blockMeshDict"
    dict_path.parent.mkdir()
    dict_path.write_text(small_pipe())
    blocks = pinn_engine.read_blockmeshdict(dict_path, "elliptic", interfaces="fixed")
    assert blocks.keys() == [f"block{k}" for k in range(5)]
    assert blocks[0].n_cells == 6 * 6 * 3 and "ScaledJacobian" in blocks[0].cell_data
    with pytest.raises(SettingsError, match="unknown method"):
        pinn_engine.read_blockmeshdict(dict_path, "mgnet")
    dict_path.write_text(small_pipe().replace("mergePatchPairs\n(\n);", "mergePatchPairs ((a b));"))
    with pytest.raises(ValueError, match="'mergePatchPairs'"):
        pinn_engine.read_blockmeshdict(dict_path)


def test_a_2d_dictionary_keeps_its_edges_across_aligned():
    """One cell across between two empty patches (the pipe's section): the Winslow grid
    solves the section as SPEC 10's, each node pair across on the planes' normal to
    round-off, as checkMesh's 2D check wants."""
    text = small_pipe().replace(" 3)", " 1)").replace("type patch", "type empty")
    result = mesh_dictionary(from_text(text))
    assert result.kept == "optimised"
    assert [k for _, k, _ in result.place.patches] == ["empty", "empty", "wall"]
    for ids in result.place.ids:
        front, back = result.points[ids[..., 0]], result.points[ids[..., 1]]
        assert np.abs(front[..., :2] - back[..., :2]).max() < 1e-14
        assert np.allclose(front[..., 2], 0.0) and np.allclose(back[..., 2], 0.5)


def test_a_cyclic_pair_stays_congruent():
    """The two sides of a cyclic pair, each solved in its plane, are one the other
    translated to round-off (OpenFOAM matches their faces to 1e-4 of their size)."""
    text = small_pipe()
    for name, other in (("inlet", "outlet"), ("outlet", "inlet")):
        text = text.replace(
            f"    {name}\n    {{\n        type patch;",
            f"    {name}\n    {{\n        type cyclic;\n        neighbourPatch {other};",
        )
    result = mesh_dictionary(from_text(text))
    sides = {name: np.unique(f) for name, _, f in result.place.patches}
    inlet, outlet = (result.points[sides[n]] for n in ("inlet", "outlet"))
    assert result.kept == "optimised"
    assert not np.allclose(inlet, result.place.points[sides["inlet"]])
    inlet, outlet = (p[np.lexsort(np.round(p[:, :2], 9).T)] for p in (inlet, outlet))
    assert np.abs(inlet[:, :2] - outlet[:, :2]).max() < 1e-15
    assert (inlet[:, 2] == 0.0).all()


@needs_openfoam
def test_a_cyclic_pair_keeps_its_neighbour_and_face_order(tmp_path):
    """Cyclic patches: their neighbourPatch is written and their faces correspond one to
    one (the dictionary's face order), so checkMesh passes."""
    text = small_pipe()
    for name, other in (("inlet", "outlet"), ("outlet", "inlet")):
        text = text.replace(
            f"    {name}\n    {{\n        type patch;",
            f"    {name}\n    {{\n        type cyclic;\n        neighbourPatch {other};",
        )
    dict_path = tmp_path / "system" / "blockMeshDict"
    dict_path.parent.mkdir()
    dict_path.write_text(text)
    case = tmp_path / "case"
    assert main([str(dict_path), "-o", str(case), "--format", "openfoam", "--quiet"]) == 0
    boundary = (case / "constant" / "polyMesh" / "boundary").read_text()
    assert boundary.count("neighbourPatch") == 2
    log = subprocess.run(["checkMesh"], cwd=case, env=foam_env(), capture_output=True, text=True)
    assert "Mesh OK." in log.stdout


def test_cgns_has_a_zone_a_block_its_bcs_and_joins(tmp_path):
    """.cgns: a structured zone a block, a BC_t a boundary face in its patch's family, and
    each of the pipe's 8 shared faces a GridConnectivity1to1_t from both sides, whose
    donor range starts at the donor's node of our first node."""
    h5py = pytest.importorskip("h5py")
    dict_path = tmp_path / "system" / "blockMeshDict"
    dict_path.parent.mkdir()
    dict_path.write_text(small_pipe())
    out = tmp_path / "pipe.cgns"
    assert main([str(dict_path), "-o", str(out), "--quiet"]) == 0
    result = mesh_dictionary(from_text(small_pipe()))
    with h5py.File(out) as f:
        base = f["Base"]
        zones = [k for k in base if isinstance(base[k], h5py.Group) and "ZoneType" in base[k]]
        assert zones == [f"block{k}" for k in range(5)]
        joins = [(z, j) for z in zones for j in base[z]["ZoneGridConnectivity"]]
        assert len(joins) == 16
        assert {n for n in base if n in ("inlet", "outlet", "wall")} == {"inlet", "outlet", "wall"}
        z, name = joins[0]
        conn = base[z]["ZoneGridConnectivity"][name]
        donor = bytes(conn[" data"][()]).decode()
        here = conn["PointRange"][" data"][()][0] - 1  # first node, 0-based (i, j, k)
        there = conn["PointRangeDonor"][" data"][()][0] - 1
        ids = result.place.ids
        assert ids[int(z[5:])][tuple(here)] == ids[int(donor[5:])][tuple(there)]
