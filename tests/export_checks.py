"""The solver formats of one 13 x 7 reference grid read back by independent readers: VTK's
PLOT3D and CGNS readers, h5py for the CGNS tree, Gmsh's own API, a parse of the SU2 text and
OpenFOAM's ``checkMesh``. Shared by the export tests of each domain kind and the ParaView
writers' test (imported as ``export_checks``)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers import foam_env
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

# the reference grid: 13 x 7 nodes of the wavy ring, small enough for every reader
NI, NJ = 13, 7
# three patches named, one side left to keep its own name
PATCHES = {"bottom": "wall", "top": "wall", "left": "inlet"}  # right keeps "right"
# patch -> number of boundary edges (2D)
EDGES = {"wall": 2 * (NI - 1), "right": NJ - 1, "inlet": NJ - 1}
# the extrusion thickness of the 3D exports
T = 0.25


def extruded(ref: np.ndarray) -> np.ndarray:
    top = ref.copy()
    top[:, 2] += T
    return np.vstack([ref, top])


def blocks(multiblock) -> dict[str, object]:
    """Leaves of a VTK multiblock by name."""
    out = {}
    it = multiblock.NewTreeIterator()
    it.VisitOnlyLeavesOn()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        out[it.GetCurrentMetaData().Get(multiblock.NAME())] = it.GetCurrentDataObject()
        it.GoToNextItem()
    return out


def read_vts(path: Path) -> np.ndarray:
    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPoints().GetData()).astype(float)


def read_plot3d(path: Path):
    """The first grid of a PLOT3D file, as VTK reads it."""
    from vtkmodules.vtkIOParallel import vtkMultiBlockPLOT3DReader

    reader = vtkMultiBlockPLOT3DReader()  # explicit: multi-grid, whole, double, byte counts
    reader.SetXYZFileName(str(path))
    reader.AutoDetectFormatOff()
    reader.MultiGridOn()
    reader.BinaryFileOn()
    reader.HasByteCountOn()
    reader.DoublePrecisionOn()
    reader.IBlankingOff()
    reader.Update()
    return reader.GetOutput().GetBlock(0)


def check_plot3d(path: Path, reference: np.ndarray, thickness: float | None) -> None:
    block = read_plot3d(path)
    nk = 1 if thickness is None else 2
    assert block.GetExtent() == (0, NI - 1, 0, NJ - 1, 0, nk - 1)
    expected = reference if thickness is None else extruded(reference)
    np.testing.assert_allclose(vtk_to_numpy(block.GetPoints().GetData()), expected, atol=1e-12)


def read_cgns(path: Path) -> dict[str, object]:
    """The zone ("Internal") and boundary patches of a CGNS file, as VTK reads them."""
    from vtkmodules.vtkIOCGNSReader import vtkCGNSReader

    reader = vtkCGNSReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    reader.EnableAllBases()
    reader.LoadBndPatchOn()
    reader.Update()
    return blocks(reader.GetOutput())


def check_cgns(path: Path, reference: np.ndarray, thickness: float | None) -> None:
    import h5py

    found = read_cgns(path)
    nk = 1 if thickness is None else 2
    expected = reference if thickness is None else extruded(reference)
    np.testing.assert_allclose(
        vtk_to_numpy(found["Internal"].GetPoints().GetData()), expected, atol=1e-12
    )
    sizes = {"wall_bottom": NI, "wall_top": NI, "right": NJ, "inlet": NJ}
    if thickness:
        sizes.update(frontAndBack_back=NI * NJ, frontAndBack_front=NI * NJ)
    assert {
        k: v.GetNumberOfPoints()
        // (nk if k in ("wall_bottom", "wall_top", "right", "inlet") else 1)
        for k, v in found.items()
        if k != "Internal"
    } == sizes

    with h5py.File(path, "r") as f:
        zone = f["Base/Zone"]
        assert zone.attrs["label"] == b"Zone_t"
        size = zone[" data"][()]  # Fortran (IndexDim, 3) stored as (3, IndexDim)
        assert size[0].tolist() == ([NI, NJ] + ([2] if thickness else []))
        ranges, families = {}, {}
        for name, bc in zone["ZoneBC"].items():
            assert bc.attrs["label"] == b"BC_t"
            assert bytes(bc[" data"][()]).decode() == "FamilySpecified"
            ranges[name] = bc["PointRange/ data"][()].tolist()
            families[name] = bytes(bc["FamilyName/ data"][()]).decode()
        k = [1, 2] if thickness else []
        assert ranges["wall_bottom"] == [[1, 1] + k[:1], [NI, 1] + k[1:]]
        assert ranges["inlet"] == [[1, 1] + k[:1], [1, NJ] + k[1:]]
        assert families == {
            "wall_bottom": "wall",
            "wall_top": "wall",
            "right": "right",
            "inlet": "inlet",
            **(
                {"frontAndBack_back": "frontAndBack", "frontAndBack_front": "frontAndBack"}
                if thickness
                else {}
            ),
        }
        family_nodes = {
            n
            for n, g in f["Base"].items()
            if isinstance(g, h5py.Group) and g.attrs["label"] == b"Family_t"
        }
        assert family_nodes == set(families.values())


def read_su2(path: Path) -> dict:
    lines = path.read_text().splitlines()
    out: dict = {"markers": {}}
    k = 0
    while k < len(lines):
        line = lines[k].strip()
        k += 1
        if line.startswith("NDIME="):
            out["ndime"] = int(line.split("=")[1])
        elif line.startswith("NELEM="):
            n = int(line.split("=")[1])
            out["elems"] = np.array([lines[k + m].split() for m in range(n)], dtype=int)
            k += n
        elif line.startswith("NPOIN="):
            n = int(line.split("=")[1].split()[0])
            dim = out["ndime"]
            out["points"] = np.array([lines[k + m].split()[:dim] for m in range(n)], dtype=float)
            k += n
        elif line.startswith("MARKER_TAG="):
            name = line.split("=")[1].strip()
            n = int(lines[k].split("=")[1])
            out["markers"][name] = np.array([lines[k + 1 + m].split() for m in range(n)], dtype=int)
            k += n + 1
    return out


def check_su2(path: Path, reference: np.ndarray) -> None:
    mesh = read_su2(path)
    assert mesh["ndime"] == 2
    assert mesh["elems"].shape == ((NI - 1) * (NJ - 1), 6) and set(mesh["elems"][:, 0]) == {9}
    np.testing.assert_array_equal(mesh["points"], reference[:, :2])
    assert {n: len(e) for n, e in mesh["markers"].items()} == EDGES
    for edges in mesh["markers"].values():
        assert set(edges[:, 0]) == {3}
    inlet = np.unique(mesh["markers"]["inlet"][:, 1:])
    assert inlet.tolist() == list(range(0, NI * NJ, NI))  # i = 0 column
    pts = mesh["points"][mesh["elems"][:, 1:5]]  # counter-clockwise quads: positive area
    x, y = pts[..., 0], pts[..., 1]
    area = 0.5 * np.sum(x * np.roll(y, -1, 1) - np.roll(x, -1, 1) * y, axis=1)
    assert (area > 0).all()


def check_gmsh(path: Path, reference: np.ndarray, thickness: float | None) -> None:
    import gmsh

    assert path.read_text().startswith("$MeshFormat\n4.1 0 8\n")
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        order = np.argsort(tags)
        expected = reference if thickness is None else extruded(reference)
        np.testing.assert_allclose(coords.reshape(-1, 3)[order], expected, atol=1e-12)
        dim = 2 if thickness is None else 3
        groups = {}
        for d, tag in gmsh.model.getPhysicalGroups():
            count = 0
            for entity in gmsh.model.getEntitiesForPhysicalGroup(d, tag):
                _, elems, _ = gmsh.model.mesh.getElements(d, entity)
                count += sum(len(e) for e in elems)
            groups[(d, gmsh.model.getPhysicalName(d, tag))] = count
    finally:
        gmsh.finalize()
    cells = (NI - 1) * (NJ - 1)
    want = {(dim, "fluid"): cells, **{(dim - 1, n): c for n, c in EDGES.items()}}
    if thickness:
        want[(2, "frontAndBack")] = 2 * cells
    assert groups == want


def check_mesh(case: Path) -> str:
    proc = subprocess.run(
        ["checkMesh", "-case", str(case)],
        capture_output=True,
        text=True,
        env=foam_env(),
        timeout=300,
    )
    return proc.stdout + proc.stderr


def foam_list(path: Path) -> list[str]:
    text = path.read_text()
    body = text[text.index("(", text.index("}")) + 1 : text.rindex(")")]
    return [ln for ln in body.splitlines() if ln.strip()]


def check_openfoam(case: Path, reference: np.ndarray) -> None:
    """Files, nodes, patches; then checkMesh (skipped, after the rest, when missing)."""
    mesh = case / "constant" / "polyMesh"
    assert sorted(p.name for p in mesh.iterdir()) == [
        "boundary",
        "faces",
        "neighbour",
        "owner",
        "points",
    ]
    assert (case / f"{case.name}.foam").exists() and (case / "system" / "controlDict").exists()
    points = np.array([ln.strip("()").split() for ln in foam_list(mesh / "points")], float)
    np.testing.assert_allclose(points, extruded(reference), atol=1e-12)
    boundary = (mesh / "boundary").read_text()
    found = dict(re.findall(r"(\w+)\s*\{[^}]*?nFaces\s+(\d+);", boundary))
    assert {k: int(v) for k, v in found.items()} == {
        **EDGES,
        "frontAndBack": 2 * (NI - 1) * (NJ - 1),
    }
    assert re.search(r"frontAndBack\s*\{\s*type\s+empty;", boundary)
    if shutil.which("checkMesh") is None:
        pytest.skip(
            "OpenFOAM's checkMesh is missing (apt-get install openfoam; .ci/run installs it)"
        )
    report = check_mesh(case)
    assert "Mesh OK." in report, report[-3000:]
    assert re.search(r"wall\s+24\s", report)  # the patch as checkMesh sees it
