"""Multi-block patches and exports (SPEC 10): the --patch X,Y naming
and its errors, CGNS zones with 1-to-1 joins checked node by node, PLOT3D multi-grid, the
merged SU2, Gmsh and OpenFOAM meshes (checkMesh, and icoFoam on the cylinder in a channel)."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from export_checks import read_su2
from helpers import EXAMPLES, foam_env, run_blocks
from multiblock_checks import write_polylines
from vtkmodules.util.numpy_support import vtk_to_numpy

from pinn_engine.io.export import write_blocks
from pinn_engine.io.export.multiblock import blocks_of
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

BOUNDARY = str(EXAMPLES / "cylinder_channel.vtp")
EDGES = str(EXAMPLES / "cylinder_channel_blocks.vtp")
CELL = 0.1  # the cylinder case: 12 blocks, 4000 cells
RADIUS = 0.5  # the cylinder's (diameter 1)
# ... drawn as a polygon of 96 vertices (make_multiblock.py): nodes on it lie this close
INSCRIBED = RADIUS * np.cos(np.pi / 96)
# One point on each boundary piece: the inlet and outlet are three pieces each, the walls
# three each, the cylinder four (the O-ring's blocks)
PATCHES = [
    *(f"-3,{y}=inlet:inflow" for y in (-1.5, 0, 1.5)),
    *(f"6,{y}=outlet:outflow" for y in (-1.5, 0, 1.5)),
    *(f"{x},{y}=walls:wall" for x in (-2, 0, 3) for y in (-2, 2)),
    *(f"{x},{y}=cylinder:wall" for x, y in ((0.5, 0), (0, 0.5), (-0.5, 0), (0, -0.5))),
]
PIECES = {"inlet": 3, "outlet": 3, "walls": 6, "cylinder": 4}


def _on_cylinder(xy: np.ndarray) -> bool:
    r = np.linalg.norm(xy[:, :2], axis=1)
    return bool(np.all((r >= INSCRIBED - 1e-12) & (r <= RADIUS + 1e-12)))


@pytest.fixture(scope="module")
def dataset():
    settings = make_settings("elliptic", cell_size=CELL)
    return run_blocks(settings, BOUNDARY, [EDGES], PATCHES).data


@pytest.fixture(scope="module")
def blocks(dataset):
    return blocks_of(dataset)


def _unique_nodes(blocks) -> int:
    return len(np.unique(np.vstack([p.reshape(-1, 3) for p in blocks.points]), axis=0))


def test_default_patch_names(tmp_path):
    """Without --patch: ``boundary`` on the outer boundary, ``hole1`` on the cylinder."""
    settings = make_settings("tfi", cell_size=CELL)
    pieces = blocks_of(run_blocks(settings, BOUNDARY, [EDGES]).data).pieces
    names = [p.name for block in pieces for p in block]
    assert sorted(set(names)) == ["boundary", "hole1"]
    assert names.count("hole1") == 4 and names.count("boundary") == 12
    on_cylinder = [p for block in pieces for p in block if p.name == "hole1"]
    assert all(p.kind == "patch" for p in on_cylinder)


def test_holes_are_numbered_as_drawn(tmp_path):
    """``hole1`` is the first hole in the file, whatever the holes' sizes: a small square
    drawn before a larger one, each in a block of its own channel part, is hole1."""
    outer = [(0, 0), (4, 0), (4, 1), (0, 1)]
    small = [(0.8, 0.4), (0.8, 0.6), (1.2, 0.6), (1.2, 0.4)]
    large = [(2.6, 0.3), (2.6, 0.7), (3.4, 0.7), (3.4, 0.3)]
    edges = [[(x, 0.0), (x, y)] for x, y in ((0.8, 0.4), (1.2, 0.4), (2.6, 0.3), (3.4, 0.3))]
    edges += [[(x, y), (x, 1.0)] for x, y in ((0.8, 0.6), (1.2, 0.6), (2.6, 0.7), (3.4, 0.7))]
    boundary = write_polylines(tmp_path / "holes.vtp", [outer, small, large], closed=True)
    blocks = write_polylines(tmp_path / "holes_blocks.vtp", edges)
    out = tmp_path / "holes.su2"
    args = [boundary, "--blocks", blocks, "--cell-size", "0.1", "--method", "tfi", "--quiet"]
    assert main([*args, "-o", str(out)]) == 0
    mesh = read_su2(out)
    assert sorted(mesh["markers"]) == ["boundary", "hole1", "hole2"]
    centre = {
        k: mesh["points"][np.unique(v[:, 1:])].mean(axis=0) for k, v in mesh["markers"].items()
    }
    assert centre["hole1"][0] == pytest.approx(1.0) and centre["hole2"][0] == pytest.approx(3.0)


def test_patch_points_name_the_nearest_pieces(blocks):
    names = [p.name for block in blocks.pieces for p in block]
    assert {n: names.count(n) for n in set(names)} == PIECES
    for pts, pieces in zip(blocks.points, blocks.pieces):
        for p in pieces:
            i0, j0, i1, j1 = p.nodes
            xy = pts[j0 : j1 + 1, i0 : i1 + 1, :2].reshape(-1, 2)
            if p.name == "cylinder":
                assert p.kind == "wall"
                assert _on_cylinder(xy)
            if p.name == "inlet":
                assert p.kind == "inflow"
                np.testing.assert_allclose(xy[:, 0], -3.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "item, message",
    [
        ("bottom=wall", "expected X,Y=NAME[:TYPE]"),
        ("1,1=x", "the point is 0.914 from the nearest boundary piece"),
        ("0.353553,0.353553=x", "as near to two boundary pieces"),
        ("0,0.5=bad name", "patch name 'bad name'"),
        ("0,0.5=x:slip", "patch type 'slip'"),
    ],
)
def test_bad_patch_points_are_one_line(tmp_path, capsys, item, message):
    out = tmp_path / "grid.vtm"
    code = main([BOUNDARY, "--blocks", EDGES, "--patch", item, "-o", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and message in err and len(err.splitlines()) == 1, err
    assert not out.exists()


def test_a_piece_named_twice_is_refused(tmp_path, capsys):
    args = ["--patch", "0.5,0=a", "--patch", "0.49,0.01=b", "-o", str(tmp_path / "g.vtm")]
    assert main([BOUNDARY, "--blocks", EDGES, *args, "--quiet"]) == 2
    assert "that piece is already named a" in capsys.readouterr().err


def test_vtm_blocks_carry_their_pieces(tmp_path):
    out = tmp_path / "grid.vtm"
    assert main([BOUNDARY, "--blocks", EDGES, "--patch", "0.5,0=cyl:wall", "-o", str(out)]) == 0
    import pyvista as pv

    grid = pv.read(out)
    ring = grid["block8"]  # the O-ring block right of the cylinder
    assert list(ring.field_data["PieceNames"]) == ["cyl"]
    assert list(ring.field_data["PieceTypes"]) == ["wall"]
    assert ring.field_data["PieceRanges"].reshape(-1, 4).shape == (1, 4)


def _groups(node) -> list:
    """A CGNS node's children (its value is the dataset " data", no child)."""
    return [v for k, v in node.items() if k != " data"]


def _cgns_ints(node, key: str) -> np.ndarray:
    return np.asarray(node[key][" data"])  # a range: rows begin, end (Fortran (dim, 2))


def test_cgns_zones_joins_and_bcs(dataset, blocks, tmp_path):
    h5py = pytest.importorskip("h5py")
    path = write_blocks(dataset, tmp_path / "grid.cgns")
    with h5py.File(path, "r") as f:
        base = f["Base"]
        zones = {
            k: v
            for k, v in base.items()
            if isinstance(v, h5py.Group) and v.attrs["label"].decode() == "Zone_t"
        }
        assert len(zones) == len(blocks.points) == 12
        coords = {}
        for k, pts in enumerate(blocks.points):
            zone = zones[f"block{k}"]
            x = np.asarray(zone["GridCoordinates/CoordinateX/ data"])  # (nj, ni) on disk
            np.testing.assert_array_equal(x, pts[..., 0])
            coords[f"block{k}"] = np.stack(
                [x, np.asarray(zone["GridCoordinates/CoordinateY/ data"])], axis=-1
            )
        joins = 0
        for name, zone in zones.items():
            for conn in _groups(zone["ZoneGridConnectivity"]):
                donor = np.frombuffer(conn[" data"][()].tobytes(), np.int8).tobytes().decode()
                here = _cgns_ints(conn, "PointRange")  # rows begin, end; 1-based (i, j)
                there = _cgns_ints(conn, "PointRangeDonor")
                t = _cgns_ints(conn, "Transform").ravel()
                matrix = np.zeros((2, 2), int)  # SIDS: donor index = T (index - begin) + begin'
                for axis, value in enumerate(t):
                    matrix[abs(value) - 1, axis] = np.sign(value)
                lo, hi = here
                steps = max(abs(hi - lo))
                for s in range(steps + 1):
                    ij = lo + s * np.sign(hi - lo)
                    dij = matrix @ (ij - lo) + there[0]
                    a = coords[name][ij[1] - 1, ij[0] - 1]
                    b = coords[donor][dij[1] - 1, dij[0] - 1]
                    assert np.array_equal(a, b), (name, donor, ij, dij)
                assert np.array_equal(matrix @ (hi - lo) + there[0], there[1])
                # the same interface seen from the donor
                back = [
                    c
                    for c in _groups(zones[donor]["ZoneGridConnectivity"])
                    if np.frombuffer(c[" data"][()].tobytes(), np.int8).tobytes().decode() == name
                    and {tuple(r) for r in _cgns_ints(c, "PointRange")} == {tuple(r) for r in there}
                ]
                assert len(back) == 1
                joins += 1
        # 16 interfaces: the O-ring's 4 diagonals, its 4 sides, 8 between the outer blocks
        assert joins == 2 * 16
        bcs = {}
        for zone in zones.values():
            for bc in _groups(zone["ZoneBC"]):
                family = bytes(np.asarray(bc["FamilyName/ data"])).decode()
                bcs[family] = bcs.get(family, 0) + 1
        assert bcs == PIECES
        kinds = {n: bytes(np.asarray(base[n]["FamilyBC/ data"])).decode() for n in PIECES}
        assert kinds == {
            "inlet": "BCInflow",
            "outlet": "BCOutflow",
            "walls": "BCWall",
            "cylinder": "BCWall",
        }


def test_cgns_read_by_vtk(dataset, blocks, tmp_path):
    pytest.importorskip("h5py")
    from vtkmodules.vtkIOCGNSReader import vtkCGNSReader

    path = write_blocks(dataset, tmp_path / "grid.cgns", extrude=0.1)
    reader = vtkCGNSReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    it = out.NewIterator()
    it.InitTraversal()
    sizes = []
    while not it.IsDoneWithTraversal():
        sizes.append(it.GetCurrentDataObject().GetNumberOfPoints())
        it.GoToNextItem()
    assert sorted(sizes) == sorted(2 * p.shape[0] * p.shape[1] for p in blocks.points)


def test_plot3d_multigrid_read_by_vtk(dataset, blocks, tmp_path):
    from vtkmodules.vtkIOParallel import vtkMultiBlockPLOT3DReader

    path = write_blocks(dataset, tmp_path / "grid.xyz")
    reader = vtkMultiBlockPLOT3DReader()
    reader.SetXYZFileName(str(path))
    reader.AutoDetectFormatOn()
    reader.Update()
    out = reader.GetOutput()
    assert out.GetNumberOfBlocks() == len(blocks.points)
    for k, pts in enumerate(blocks.points):
        got = vtk_to_numpy(out.GetBlock(k).GetPoints().GetData())
        np.testing.assert_array_equal(got, pts.reshape(-1, 3))


def _su2(path) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    text = path.read_text().splitlines()
    n_elem = int(next(t for t in text if t.startswith("NELEM=")).split()[1])
    start = text.index(f"NELEM= {n_elem}") + 1
    quads = np.array([t.split()[1:5] for t in text[start : start + n_elem]], int)
    n_poin = int(text[start + n_elem].split()[1])
    pts = np.array([t.split()[:2] for t in text[start + n_elem + 1 : start + n_elem + 1 + n_poin]])
    markers, k = {}, start + n_elem + 2 + n_poin
    while k < len(text):
        name, count = text[k].split()[1], int(text[k + 1].split()[1])
        markers[name] = np.array([t.split()[1:] for t in text[k + 2 : k + 2 + count]], int)
        k += 2 + count
    return pts.astype(float), quads, markers


def test_su2_is_one_merged_mesh(dataset, blocks, tmp_path):
    pts, quads, markers = _su2(write_blocks(dataset, tmp_path / "grid.su2"))
    total = sum(p.shape[0] * p.shape[1] for p in blocks.points)
    assert len(pts) == _unique_nodes(blocks) < total  # shared nodes written once
    assert len(np.unique(pts, axis=0)) == len(pts)
    assert len(quads) == 4000 and np.array_equal(np.unique(quads), np.arange(len(pts)))
    # counter-clockwise quads: positive areas
    x, y = pts[quads, 0], pts[quads, 1]
    assert np.all(0.5 * (x * np.roll(y, -1, 1) - np.roll(x, -1, 1) * y).sum(axis=1) > 0)
    assert set(markers) == set(PIECES)
    cyl = pts[markers["cylinder"].ravel()]
    assert _on_cylinder(cyl)
    assert len(markers["cylinder"]) == sum(
        max(p.nodes[2] - p.nodes[0], p.nodes[3] - p.nodes[1])
        for block in blocks.pieces
        for p in block
        if p.name == "cylinder"
    )


def test_gmsh_reads_the_merged_mesh(dataset, blocks, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    path = write_blocks(dataset, tmp_path / "grid.msh")
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(str(path))
        tags, _, _ = gmsh.model.mesh.getNodes()
        assert len(tags) == _unique_nodes(blocks)
        groups = {
            gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()
        }
        assert set(groups) == set(PIECES) | {"fluid"}
        types, elems, _ = gmsh.model.mesh.getElements(2)
        assert list(types) == [3] and len(elems[0]) == 4000
    finally:
        gmsh.finalize()


def test_a_side_that_meets_no_node_is_refused(dataset, tmp_path):
    """Blocks that do not meet node to node (here: one block's nodes moved) are refused."""
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

    from pinn_engine.errors import InputError

    copy = vtkMultiBlockDataSet()
    copy.DeepCopy(dataset)
    pts = vtk_to_numpy(copy.GetBlock(0).GetPoints().GetData())
    pts[:, 0] += 1e-3
    with pytest.raises(InputError, match="do not meet node to node"):
        write_blocks(copy, tmp_path / "grid.su2")
    assert not (tmp_path / "grid.su2").exists()


NO_FOAM = "OpenFOAM's {} is missing (apt-get install openfoam; .ci/run installs it)"


def test_openfoam_case_passes_checkmesh(dataset, blocks, tmp_path):
    case = write_blocks(dataset, tmp_path / "case", fmt="openfoam", extrude=0.1)
    boundary = (case / "constant/polyMesh/boundary").read_text()
    for name, kind in (("inlet", "patch"), ("walls", "wall"), ("frontAndBack", "empty")):
        assert re.search(rf"{name}\s*\{{\s*type\s+{kind};", boundary), name
    if shutil.which("checkMesh") is None:
        pytest.skip(NO_FOAM.format("checkMesh"))
    proc = subprocess.run(
        ["checkMesh", "-case", str(case)], capture_output=True, text=True, env=foam_env()
    )
    assert "Mesh OK." in proc.stdout, proc.stdout[-3000:]
    assert re.search(r"cells:\s+4000\b", proc.stdout)


# icoFoam on the cylinder in a channel: Re = U D / nu = 1 x 1 / NU = 20, steady (no vortex
# street below Re of about 47); DT keeps the Courant number below 1 on the finest cells
NU, DT, END = 0.05, 0.02, 10
CASE_FILES = {
    "0/U": (
        "volVectorField",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\nboundaryField\n{\n"
        "    inlet { type fixedValue; value uniform (1 0 0); }\n"
        "    outlet { type zeroGradient; }\n    walls { type noSlip; }\n"
        "    cylinder { type noSlip; }\n    frontAndBack { type empty; }\n}\n",
    ),
    "0/p": (
        "volScalarField",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\nboundaryField\n{\n"
        "    inlet { type zeroGradient; }\n    outlet { type fixedValue; value uniform 0; }\n"
        "    walls { type zeroGradient; }\n    cylinder { type zeroGradient; }\n"
        "    frontAndBack { type empty; }\n}\n",
    ),
    "constant/transportProperties": ("dictionary", f"nu [0 2 -1 0 0 0 0] {NU};\n"),
    "system/controlDict": (
        "dictionary",
        f"application icoFoam;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\n"
        f"endTime {END};\ndeltaT {DT};\nwriteControl runTime;\nwriteInterval {END};\n",
    ),
    "system/fvSchemes": (
        "dictionary",
        "ddtSchemes { default Euler; }\ngradSchemes { default Gauss linear; }\n"
        "divSchemes { default none; div(phi,U) Gauss linearUpwind grad(U); }\n"
        "laplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
    ),
    "system/fvSolution": (
        "dictionary",
        "solvers\n{\n    p { solver PCG; preconditioner DIC; tolerance 1e-8; relTol 0.05; }\n"
        "    pFinal { $p; relTol 0; }\n"
        "    U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-8; relTol 0; }\n}\n"
        "PISO { nCorrectors 2; nNonOrthogonalCorrectors 1; pRefCell 0; pRefValue 0; }\n",
    ),
}
STEADY = 1e-4  # the last step's initial Ux residual: the flow no longer changes
CONTINUITY = 1e-8  # the last step's local continuity error ("sum local")


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("icoFoam") is None, reason=NO_FOAM.format("icoFoam"))
def test_icofoam_reaches_a_steady_state_on_the_cylinder(tmp_path):
    case = tmp_path / "cylinder"
    command = [BOUNDARY, "--blocks", EDGES, "--cell-size", str(CELL), "--format", "openfoam"]
    command += ["--extrude", "0.1", *(f"--patch={p}" for p in PATCHES), "-o", str(case)]
    assert main([*command, "--quiet"]) == 0
    for rel, (cls, body) in CASE_FILES.items():
        header = f"FoamFile {{ version 2.0; format ascii; class {cls}; object {rel[2:]}; }}\n"
        (case / rel).parent.mkdir(parents=True, exist_ok=True)
        (case / rel).write_text(header.replace(rel[2:], rel.split("/")[-1]) + body)
    proc = subprocess.run(
        ["icoFoam", "-case", str(case)],
        capture_output=True,
        text=True,
        env=foam_env(),
        timeout=120,
    )
    log = proc.stdout
    assert proc.returncode == 0 and log.rstrip().endswith("End"), log[-3000:]
    courant = [float(v) for v in re.findall(r"Courant Number mean: \S+ max: (\S+)", log)]
    assert len(courant) == round(END / DT) and max(courant) < 1.0
    ux = [float(v) for v in re.findall(r"Solving for Ux, Initial residual = ([^,]+)", log)]
    assert ux[-1] < STEADY < ux[0]
    local = [float(v) for v in re.findall(r"sum local = ([^,]+)", log)]
    assert local[-1] < CONTINUITY


def test_a_point_where_a_straight_side_is_split_names_both_pieces(tmp_path, capsys):
    """Automatic blocking splits the step's outlet at its middle (a block corner on a
    straight side): a point there names both halves; at the step's lip (a corner of the
    boundary) it is refused as before."""
    step = str(EXAMPLES / "step.vtp")
    out = tmp_path / "case"
    argv = [step, "--blocks", "auto", "--patch", "-2,1.5=inlet:inflow"]
    argv += ["--patch", "6,1=outlet:outflow", "--format", "openfoam", "--extrude", "0.1"]
    assert main([*argv, "-o", str(out), "--quiet"]) == 0
    boundary = (out / "constant" / "polyMesh" / "boundary").read_text()
    faces = dict(re.findall(r"(\w+)\s*\{[^}]*?nFaces\s+(\d+);", boundary))
    assert int(faces["outlet"]) == 2 * int(faces["inlet"])  # the whole outlet, twice the inlet
    code = main([step, "--blocks", "auto", "--patch", "0,1=lip", "-o", str(tmp_path / "g.vtm")])
    assert code == 2 and "a corner of the boundary" in capsys.readouterr().err
