"""Solver formats of a hexahedral grid (SPEC 8 and 11): each export of a small grid
read back by an independent reader (VTK's PLOT3D and CGNS readers, h5py, Gmsh's API, a parse
of the SU2 text, OpenFOAM's checkMesh) with its hexahedra, positive volumes and patches."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest
import pyvista as pv
from export_checks import check_mesh, foam_list, read_cgns, read_plot3d, read_su2
from helpers import ROOT
from vtkmodules.util.numpy_support import vtk_to_numpy

from pinn_engine.errors import InputError
from pinn_engine.io import export
from pinn_engine.kinds.hexa.mesh import hexa_grid, mesh_surface
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

SURFACE = ROOT / "example_data" / "hexa_bend.vtp"
NI, NJ, NK = 5, 4, 3
CELLS = (NI - 1) * (NJ - 1) * (NK - 1)
PATCHES = ["imin=inlet:inflow", "imax=outlet:outflow", "jmin=wall", "jmax=wall"]
# patch -> boundary faces: i sides (NJ - 1)(NK - 1), j sides (NI - 1)(NK - 1), k sides ...
FACES = {"inlet": 6, "outlet": 6, "wall": 16, "kmin": 12, "kmax": 12}
# hexahedron faces as VTK (and Gmsh) number a hexahedron's corners
HEX_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


@pytest.fixture(scope="module")
def grid():
    return pv.wrap(
        hexa_grid(mesh_surface(str(SURFACE), make_settings("tfi", size=(NI, NJ, NK))), "tfi")
    )


def corner_volumes(points: np.ndarray, hexes: np.ndarray) -> np.ndarray:
    """The triple product of each hexahedron's edges at its corner 0 (VTK's order): positive
    for a right-handed cell."""
    p = points[hexes]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 3] - p[:, 0]), p[:, 4] - p[:, 0])


def facing_out(points: np.ndarray, hexes: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Whether each boundary quad's normal (its vertex order) points away from its cell."""
    cell_of = {
        frozenset(h[k] for k in f): c for c, h in enumerate(hexes.tolist()) for f in HEX_FACES
    }
    owner = np.array([cell_of[frozenset(f)] for f in faces.tolist()])
    q = points[faces]
    normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
    away = q.mean(axis=1) - points[hexes[owner]].mean(axis=1)
    return np.einsum("ij,ij->i", normal, away) > 0


def test_plot3d_read_by_vtk(grid, tmp_path):
    block = read_plot3d(export.write(grid, tmp_path / "g.xyz"))
    assert block.GetExtent() == (0, NI - 1, 0, NJ - 1, 0, NK - 1)
    np.testing.assert_allclose(vtk_to_numpy(block.GetPoints().GetData()), grid.points, atol=1e-12)


def test_cgns_one_3d_zone_with_typed_bcs(grid, tmp_path):
    h5py = pytest.importorskip("h5py")
    path = export.write(grid, tmp_path / "g.cgns", patches=PATCHES)
    found = read_cgns(path)
    np.testing.assert_allclose(
        vtk_to_numpy(found["Internal"].GetPoints().GetData()), grid.points, atol=1e-12
    )
    points = {"inlet": NJ * NK, "outlet": NJ * NK, "wall_jmin": NI * NK, "wall_jmax": NI * NK}
    points.update(kmin=NI * NJ, kmax=NI * NJ)
    assert {k: v.GetNumberOfPoints() for k, v in found.items() if k != "Internal"} == points
    with h5py.File(path, "r") as f:
        assert f["Base"][" data"][()].tolist() == [3, 3]
        assert f["Base/Zone"][" data"][()][0].tolist() == [NI, NJ, NK]
        bcs = f["Base/Zone/ZoneBC"]
        ranges = {name: bc["PointRange/ data"][()].tolist() for name, bc in bcs.items()}
        assert ranges["inlet"] == [[1, 1, 1], [1, NJ, NK]]
        assert ranges["wall_jmax"] == [[1, NJ, 1], [NI, NJ, NK]]
        assert ranges["kmin"] == [[1, 1, 1], [NI, NJ, 1]]
        kinds = (("inlet", "BCInflow"), ("outlet", "BCOutflow"), ("wall", "BCWall"))
        for name, kind in (*kinds, ("kmin", "BCTypeUserDefined")):
            assert bytes(f[f"Base/{name}/FamilyBC/ data"][()]).decode() == kind


def test_cgns_through_the_helper_python_keeps_the_types(grid, tmp_path, monkeypatch):
    """Where this Python's h5py is unusable (ParaView's), the helper Python writes the file
    (here this venv's Python behind a wrapper script, so that it counts as another)."""
    h5py = pytest.importorskip("h5py")
    import sys

    from pinn_engine.io.export import cgns

    helper = tmp_path / "python"
    helper.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    helper.chmod(0o755)
    monkeypatch.setenv("PINN_MESH_PYTHON", str(helper))
    monkeypatch.setattr(cgns, "_H5PY", [None])
    path = export.write(grid, tmp_path / "g.cgns", patches=PATCHES)
    with h5py.File(path, "r") as f:
        assert f["Base/Zone"][" data"][()][0].tolist() == [NI, NJ, NK]
        assert bytes(f["Base/inlet/FamilyBC/ data"][()]).decode() == "BCInflow"
        assert len(f["Base/Zone/ZoneBC"]) == 6


def test_su2_hexahedra_and_markers(grid, tmp_path):
    mesh = read_su2(export.write(grid, tmp_path / "g.su2", patches=PATCHES))
    assert mesh["ndime"] == 3
    assert mesh["elems"].shape == (CELLS, 10) and set(mesh["elems"][:, 0]) == {12}
    np.testing.assert_array_equal(mesh["points"], grid.points)
    hexes = mesh["elems"][:, 1:9]
    assert (corner_volumes(mesh["points"], hexes) > 0).all()
    assert {n: len(e) for n, e in mesh["markers"].items()} == FACES
    for faces in mesh["markers"].values():
        assert set(faces[:, 0]) == {9}
        assert facing_out(mesh["points"], hexes, faces[:, 1:]).all()


def test_gmsh_hexahedra_and_physical_surfaces(grid, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    path = export.write(grid, tmp_path / "g.msh", patches=PATCHES)
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        points = np.empty((len(tags), 3))
        points[tags.astype(int) - 1] = coords.reshape(-1, 3)
        groups = {}
        for d, tag in gmsh.model.getPhysicalGroups():
            elements = []
            for entity in gmsh.model.getEntitiesForPhysicalGroup(d, tag):
                kinds, _, nodes = gmsh.model.mesh.getElements(d, entity)
                width = {5: 8, 3: 4}
                elements += [n.reshape(-1, width[k]) - 1 for k, n in zip(kinds, nodes)]
            groups[(d, gmsh.model.getPhysicalName(d, tag))] = np.vstack(elements).astype(int)
    finally:
        gmsh.finalize()
    np.testing.assert_allclose(points, grid.points, atol=1e-12)
    hexes = groups.pop((3, "fluid"))
    assert len(hexes) == CELLS and (corner_volumes(points, hexes) > 0).all()
    assert {name: len(f) for (d, name), f in groups.items() if d == 2} == FACES
    for faces in groups.values():
        assert facing_out(points, hexes, faces).all()


def test_openfoam_polymesh_passes_checkmesh(grid, tmp_path):
    case = export.write(grid, tmp_path / "case", "openfoam", patches=PATCHES)
    mesh = case / "constant" / "polyMesh"
    points = np.array([ln.strip("()").split() for ln in foam_list(mesh / "points")], float)
    np.testing.assert_allclose(points, grid.points, atol=1e-12)
    boundary = (mesh / "boundary").read_text()
    found = re.findall(r"(\w+)\s*\{\s*type\s+(\w+);[^}]*?nFaces\s+(\d+);", boundary)
    assert {name: (kind, int(n)) for name, kind, n in found} == {
        "inlet": ("patch", 6),
        "outlet": ("patch", 6),
        "wall": ("wall", 16),
        "kmin": ("patch", 12),
        "kmax": ("patch", 12),
    }
    if shutil.which("checkMesh") is None:
        pytest.skip("OpenFOAM's checkMesh is missing (bash scripts/setup_openfoam.sh)")
    report = check_mesh(case)
    assert "Mesh OK." in report, report[-3000:]
    assert re.search(rf"hexahedra:\s+{CELLS}\b", report)


def test_vts_carries_patch_names_and_three_indices(grid, tmp_path):
    out = pv.read(export.write(grid, tmp_path / "g.vts", patches=PATCHES))
    assert list(out.field_data["PatchNames"]) == ["inlet", "outlet", "wall", "wall", "kmin", "kmax"]
    assert (
        list(out.field_data["PatchTypes"]) == ["inflow", "outflow", "wall", "wall"] + ["patch"] * 2
    )
    assert out.point_data["k"].reshape(NK, NJ, NI)[:, 0, 0].tolist() == list(range(NK))
    assert "ScaledJacobian" in out.cell_data


def test_left_handed_grid_and_2d_sides_are_refused(grid, tmp_path):
    g = np.asarray(grid.points).reshape(NK, NJ, NI, 3)[:, :, ::-1]  # i reversed
    flipped = pv.StructuredGrid(*(np.ascontiguousarray(g[..., a].T) for a in range(3)))
    with pytest.raises(InputError, match="not right-handed in"):
        export.write(flipped, tmp_path / "g.su2")
    with pytest.raises(InputError, match="SIDE one of imin, imax, jmin, jmax, kmin, kmax"):
        export.write(grid, tmp_path / "g.su2", patches=["bottom=wall"])
    with pytest.raises(InputError, match="3D already"):
        export.write(grid, tmp_path / "g.xyz", extrude=0.1)
    assert not list(tmp_path.iterdir())


def test_cli_writes_openfoam_with_patches_and_refuses_2d_sides(tmp_path, capsys):
    case = tmp_path / "case"
    argv = [str(SURFACE), "--size", str(NI), str(NJ), str(NK), "--method", "tfi"]
    assert main([*argv, "--format", "openfoam", "--patch", "kmin=floor:wall", "-o", str(case)]) == 0
    boundary = (case / "constant" / "polyMesh" / "boundary").read_text()
    assert re.search(r"floor\s*\{\s*type\s+wall;", boundary)
    out = tmp_path / "g.msh"
    assert main([*argv, "--patch", "bottom=wall", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "SIDE one of imin, imax" in err and not out.exists()
