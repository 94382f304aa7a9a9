"""O- and C-grids in the solver formats (SPEC 9): the seam and the wake cut recorded."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from helpers import foam_env
from vtkmodules.util.numpy_support import vtk_to_numpy

from pinn_engine.bodies import bodygrid
from pinn_engine.bodies.airfoil import body_from_points, circle, load_body, naca4
from pinn_engine.errors import InputError
from pinn_engine.io.export import write
from pinn_engine.io.export.patches import body_patch_names as patch_names
from pinn_engine.io.pipeline import to_vtk
from pinn_engine.kinds.body.mesh import mesh_body
from pinn_engine.quality import non_orthogonality

NI, NJ = {"o": 41, "c": 61}, 13


@pytest.fixture(scope="module", params=["o", "c"])
def case(request):
    topology = request.param
    body = load_body(naca="0012", te="blunt" if topology == "o" else "sharp")
    result = mesh_body(body, circle(body, 8), topology, "tfi", NI[topology], NJ, wall_spacing=1e-3)
    return topology, result, to_vtk(result, patch_names(topology))


def _su2(path):
    text = path.read_text().split("\n")
    at = {line.split("=")[0]: k for k, line in enumerate(text) if "=" in line}
    nelem = int(text[at["NELEM"]].split("=")[1])
    elems = np.array(
        [list(map(int, r.split()[1:5])) for r in text[at["NELEM"] + 1 : at["NELEM"] + 1 + nelem]]
    )
    npoin = int(text[at["NPOIN"]].split("=")[1])
    pts = np.array(
        [list(map(float, r.split()[:2])) for r in text[at["NPOIN"] + 1 : at["NPOIN"] + 1 + npoin]]
    )
    markers, k = {}, at["NMARK"] + 1
    while k < len(text) and text[k].startswith("MARKER_TAG"):
        name = text[k].split("=")[1].strip()
        n = int(text[k + 1].split("=")[1])
        markers[name] = np.array([list(map(int, r.split()[1:])) for r in text[k + 2 : k + 2 + n]])
        k += 2 + n
    return elems, pts, markers


def _area(pts, quad):
    p = pts[quad]
    return 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])


def test_su2_merges_the_seam_or_cut(case, tmp_path):
    topology, result, grid = case
    ni, nj = NI[topology], NJ
    elems, pts, markers = _su2(write(grid, tmp_path / "g.su2"))
    n_wake = result.report["topology"]["wake_nodes"]
    merged = nj if topology == "o" else n_wake + 1
    assert len(pts) == ni * nj - merged  # each coincident node written once
    assert len(elems) == (ni - 1) * (nj - 1)
    assert all(_area(pts, q) > 0 for q in elems)  # counter-clockwise quads
    expected = {"wall": ni - 1 if topology == "o" else ni - 1 - 2 * n_wake, "farfield": ni - 1}
    if topology == "c":
        expected["outflow"] = 2 * (nj - 1)
    assert {k: len(v) for k, v in markers.items()} == expected
    # every edge is shared by two quads except the marker edges: the seam/cut is internal
    edges = {}
    for q in elems:
        for a, b in zip(q, np.roll(q, -1)):
            edges[frozenset((a, b))] = edges.get(frozenset((a, b)), 0) + 1
    boundary = {e for e, n in edges.items() if n == 1}
    assert boundary == {frozenset(e) for v in markers.values() for e in v}


def test_gmsh_reads_the_merged_mesh(case, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    topology, result, grid = case
    path = write(grid, tmp_path / "g.msh")
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, _, _ = gmsh.model.mesh.getNodes()
        names = {gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
    finally:
        gmsh.finalize()
    n_wake = result.report["topology"]["wake_nodes"]
    merged = NJ if topology == "o" else n_wake + 1
    assert len(tags) == NI[topology] * NJ - merged
    assert names == ({"wall", "farfield", "fluid"} | ({"outflow"} if topology == "c" else set()))


@pytest.mark.parametrize("thickness", [None, 0.1])
def test_cgns_records_the_seam_or_cut(case, tmp_path, thickness):
    h5py = pytest.importorskip("h5py")
    from vtkmodules.vtkIOCGNSReader import vtkCGNSReader

    topology, result, grid = case
    path = write(grid, tmp_path / "g.cgns", extrude=thickness)
    ni, nj, nw = NI[topology], NJ, result.report["topology"]["wake_nodes"]
    with h5py.File(path, "r") as f:
        conn = f["Base/Zone/ZoneGridConnectivity"]
        got = {
            name: (
                conn[name]["PointRange/ data"][()].tolist(),
                conn[name]["PointRangeDonor/ data"][()].tolist(),
                conn[name]["Transform/ data"][()].tolist(),
            )
            for name in conn
        }
        bcs = sorted(
            bytes(bc["FamilyName/ data"][()]).decode() for bc in f["Base/Zone/ZoneBC"].values()
        )
    k = ([1], [2]) if thickness else ([], [])
    if topology == "o":
        a, b, t = [[1, 1] + k[0], [1, nj] + k[1]], [[ni, 1] + k[0], [ni, nj] + k[1]], [1, 2]
        assert bcs == sorted(["farfield", "wall"] + (["frontAndBack"] * 2 if thickness else []))
    else:
        a, b = [[1, 1] + k[0], [nw + 1, 1] + k[1]], [[ni, 1] + k[0], [ni - nw, 1] + k[1]]
        t = [-1, -2]
        assert bcs == sorted(
            ["farfield", "outflow", "outflow", "wall"] + (["frontAndBack"] * 2 if thickness else [])
        )
    t = t + ([3] if thickness else [])
    name = "seam" if topology == "o" else "wake_cut"
    assert got == {f"{name}_a": (a, b, t), f"{name}_b": (b, a, t)}
    reader = vtkCGNSReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    reader.EnableAllBases()
    reader.Update()
    block = reader.GetOutput().GetBlock(0).GetBlock(0)
    pts = vtk_to_numpy(block.GetPoints().GetData())
    assert len(pts) == ni * nj * (2 if thickness else 1)


def test_plot3d_and_openfoam(case, tmp_path):
    from vtkmodules.vtkIOParallel import vtkMultiBlockPLOT3DReader

    topology, result, grid = case
    path = write(grid, tmp_path / "g.xyz")
    reader = vtkMultiBlockPLOT3DReader()
    reader.SetXYZFileName(str(path))
    reader.Update()
    pts = vtk_to_numpy(reader.GetOutput().GetBlock(0).GetPoints().GetData())
    np.testing.assert_allclose(pts[:, :2], result.points.reshape(-1, 2), atol=1e-12)
    with pytest.raises(InputError, match="Gmsh in 2D"):
        write(grid, tmp_path / "g.msh", extrude=0.1)


def test_openfoam_joins_the_seam_or_cut(case, tmp_path):
    topology, result, grid = case
    ni, nj, nw = NI[topology], NJ, result.report["topology"]["wake_nodes"]
    mesh = write(grid, tmp_path / "case", "openfoam") / "constant" / "polyMesh"

    def numbers(name):
        text = (mesh / name).read_text()
        body = text[text.index("(", text.index("}")) + 1 : text.rindex(")")]
        return body

    n_cells = (ni - 1) * (nj - 1)
    owner = np.array(numbers("owner").split(), dtype=int)
    neighbour = np.array(numbers("neighbour").split(), dtype=int)
    # every cell has 6 faces: 4 sides + 2 ends
    counts = np.bincount(np.concatenate([owner, neighbour]), minlength=n_cells)
    assert np.all(counts == 6)
    assert np.all(owner[: len(neighbour)] < neighbour)
    boundary = (mesh / "boundary").read_text()
    patches = {k: v for k, v in re.findall(r"(\w+)\s*\{([^}]*)\}", boundary) if "nFaces" in v}
    faces = {name: int(re.search(r"nFaces\s+(\d+);", patches[name])[1]) for name in patches}
    kinds = {name: re.search(r"type\s+(\w+);", patches[name])[1] for name in patches}
    assert (kinds["wall"], kinds["farfield"]) == ("wall", "patch")
    assert faces["farfield"] == ni - 1
    assert faces["wall"] == (ni - 1 if topology == "o" else ni - 1 - 2 * nw)
    # internal faces: all shared cell sides, the seam or cut included
    sides = faces["wall"] + faces["farfield"] + (2 * (nj - 1) if topology == "c" else 0)
    assert len(neighbour) == (4 * n_cells - sides) // 2
    if shutil.which("checkMesh"):
        proc = subprocess.run(
            ["checkMesh", "-case", str(mesh.parents[1])],
            env=foam_env(),
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert "Mesh OK" in proc.stdout, proc.stdout[-2000:] + proc.stderr[-2000:]
        # quality.non_orthogonality is checkMesh's figure
        reported = float(re.search(r"non-orthogonality Max: ([\d.eE+-]+)", proc.stdout)[1])
        ours = max(a.max() for a in non_orthogonality(result.points).values())
        assert reported == pytest.approx(ours, abs=0.01)


def test_a_blunt_c_grid_exports_its_base_as_wall_and_joins_its_cut(tmp_path):
    """A blunt trailing edge's C-grid (the cut leaving the base's middle):
    the base's edges belong to the wall patch, and the cut's nodes, the base's middle
    included, are merged in SU2 and OpenFOAM (checkMesh, where installed, finds no fault but
    the wake's aspect ratio) and joined in CGNS."""
    xy = naca4("4417")
    xy[:, 1] += np.where(np.arange(len(xy)) <= len(xy) // 2, 0.5, -0.5) * 0.007 * xy[:, 0]
    body = body_from_points(xy, "base07")
    ni, nj = 121, 33
    result = mesh_body(body, circle(body, 15), "c", "elliptic", ni, nj, wall_spacing=1e-4)
    grid = to_vtk(result, patch_names("c"))
    nw = result.report["topology"]["wake_nodes"]
    elems, pts, markers = _su2(write(grid, tmp_path / "g.su2"))
    assert len(pts) == ni * nj - (nw + 1)  # the cut's nodes, the base's middle too, once
    assert len(markers["wall"]) == ni - 1 - 2 * nw
    mid_x = 0.5 * (body.surface[0, 0] + body.surface[-1, 0])
    on_base = np.all(np.abs(pts[markers["wall"], 0] - mid_x) < 1e-12, axis=1)
    assert on_base.sum() == bodygrid.C_BASE_INTERVALS  # the base's edges are wall
    edges = {}
    for q in elems:
        for a, b in zip(q, np.roll(q, -1)):
            edges[frozenset((a, b))] = edges.get(frozenset((a, b)), 0) + 1
    boundary = {e for e, n in edges.items() if n == 1}
    assert boundary == {frozenset(e) for v in markers.values() for e in v}  # the cut: internal
    h5py = pytest.importorskip("h5py")
    with h5py.File(write(grid, tmp_path / "g.cgns"), "r") as f:
        wall_range = f["Base/Zone/ZoneBC/wall/PointRange/ data"][()].tolist()
        cut = f["Base/Zone/ZoneGridConnectivity/wake_cut_a/PointRange/ data"][()].tolist()
    assert wall_range == [[nw + 1, 1], [ni - nw, 1]]  # from the base's middle round to it
    assert cut == [[1, 1], [nw + 1, 1]]
    mesh = write(grid, tmp_path / "case", "openfoam") / "constant" / "polyMesh"
    text = (mesh / "boundary").read_text()
    wall = re.search(r"wall\s*\{([^}]*)\}", text)[1]
    assert int(re.search(r"nFaces\s+(\d+);", wall)[1]) == ni - 1 - 2 * nw
    if shutil.which("checkMesh"):
        proc = subprocess.run(
            ["checkMesh", "-case", str(mesh.parents[1])],
            env=foam_env(),
            capture_output=True,
            text=True,
            timeout=300,
        )
        # the thin cells far down the wake flag the aspect ratio, as on any y+ ~ 1 C-grid
        failed = [line for line in proc.stdout.splitlines() if line.strip().startswith("***")]
        assert all("aspect ratio" in line for line in failed), proc.stdout[-2000:]
        assert "Non-orthogonality check OK" in proc.stdout
