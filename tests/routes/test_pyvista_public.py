"""The pyvista route's public calls as a pip user scripts them: a multi-block grid saved to
every solver format by ``pinn_engine.save`` and the accessor's ``save``, meshio's argument
order, airfoils read and meshed without a body file, and refusals in the types pyvista
users expect (an unknown keyword a ``TypeError``, a bad value a ``ValueError``, a missing
extra an ``ImportError``), each one short line naming no internal function."""

from __future__ import annotations

import re

import h5py
import numpy as np
import pytest
import pyvista as pv
from export_checks import read_su2
from helpers import EXAMPLES

import pinn_engine
from pinn_engine.errors import KeywordError, MissingExtraError, PinnMeshError

INTERNAL = re.compile(r"save_mesh|__call__|PinnMeshAccessor|Settings|\n")


@pytest.fixture(scope="module")
def lshape():
    """The L-shape, its two blocks meshed (elliptic: no training) by the accessor."""
    boundary = pv.read(EXAMPLES / "lshape.vtp")
    edges = pv.read(EXAMPLES / "lshape_blocks.vtp")
    grid = boundary.pinn_mesh(blocks=edges, cell_size=0.25, method="elliptic")
    return boundary, grid


def nodes(grid: pv.MultiBlock) -> np.ndarray:
    """The distinct nodes of the blocks (shared interface nodes once)."""
    every = np.concatenate([np.asarray(b.points) for b in grid])
    return np.unique(np.round(every, 9), axis=0)


def test_a_multiblock_grid_saves_to_every_solver_format(lshape, tmp_path):
    boundary, grid = lshape
    su2 = read_su2(pinn_engine.save(grid, tmp_path / "g.su2"))
    assert su2["points"].shape[0] == len(nodes(grid))  # one merged mesh, shared nodes once
    assert su2["elems"].shape[0] == sum(b.n_cells for b in grid)
    assert set(su2["markers"]) == {"boundary"}
    with h5py.File(pinn_engine.save(grid, tmp_path / "g.cgns"), "r") as f:
        assert sorted(k for k in f["Base"] if k.startswith("block")) == ["block0", "block1"]
        assert "ZoneBC" in f["Base/block0"] and "ZoneGridConnectivity" in f["Base/block0"]
    case = pinn_engine.save(grid, tmp_path / "case", format="openfoam")
    assert (case / "constant" / "polyMesh" / "boundary").is_file()
    assert pinn_engine.save(grid, tmp_path / "g.vtm").is_file()
    back = pv.read(tmp_path / "g.vtm")
    assert back.n_blocks == 2 and back["block0"].n_points == grid["block0"].n_points
    # the accessor's save takes its last grid, the multi-block one
    assert boundary.pinn_mesh.save(tmp_path / "last.su2").is_file()


def test_a_multiblock_grid_refuses_side_names(lshape, tmp_path):
    with pytest.raises(ValueError, match=r"named when it is meshed \(patches=\["):
        pinn_engine.save(lshape[1], tmp_path / "g.su2", patches={"bottom": "wall"})


def test_save_takes_meshio_s_order_too(tmp_path):
    grid = pv.read(EXAMPLES / "fig2.vtp").pinn_mesh(size=(11, 6), method="tfi")
    first = pinn_engine.save(grid, tmp_path / "a.su2")
    second = pinn_engine.save(tmp_path / "b.su2", grid)  # meshio.write(path, mesh)
    assert first.read_text() == second.read_text()


def test_read_airfoil_and_a_body_free_naca_grid():
    body = pinn_engine.read_airfoil(EXAMPLES / "naca0012.dat")
    assert isinstance(body, pv.PolyData) and body.n_points > 100 and body.n_cells == 1
    grid = body.pinn_mesh(topology="o", method="elliptic", size=(65, 9))
    assert grid.dimensions == (65, 9, 1)
    naca = pv.PolyData().pinn_mesh(naca="0012", topology="o", method="elliptic", size=(65, 9))
    assert pinn_engine.report(naca)["quality"]["folded_cells"] == 0
    with pytest.raises(ValueError, match="Selig or Lednicer"):
        pinn_engine.read_airfoil(EXAMPLES / "fig2.vtp")


KEYWORD_CALLS = [
    (lambda b: b.pinn_mesh(siz=(11, 6)), r"^pinn_mesh: unknown keyword siz=; did you mean size="),
    (lambda b: b.pinn_mesh(learning_rat=1e-3), r"did you mean learning_rate=\?$"),
    (lambda b: b.pinn_mesh(zzz=1), r"^pinn_mesh: unknown keyword zzz=; help\(pinn_mesh\)"),
    (
        lambda b: b.pinn_mesh.save("x.su2", patchs=1),
        r"^boundary.pinn_mesh.save: unknown keyword patchs=; did you mean patches=\?$",
    ),
    (lambda b: pinn_engine.save(b, "x.su2", extrud=1), r"^pinn_engine.save: unknown keyword ex"),
    (lambda b: pinn_engine.save(b, "x.su2", None, None, 1), r"^pinn_engine.save: too many posit"),
]


@pytest.mark.parametrize(("call", "message"), KEYWORD_CALLS)
def test_an_unknown_keyword_is_a_type_error_in_one_short_line(call, message):
    boundary = pv.read(EXAMPLES / "fig2.vtp")
    with pytest.raises(TypeError, match=message) as caught:
        call(boundary)
    assert isinstance(caught.value, KeywordError) and isinstance(caught.value, PinnMeshError)
    assert not INTERNAL.search(str(caught.value)) and len(str(caught.value)) < 100


def test_the_hexahedral_keywords_are_checked_the_same_way():
    from pinn_engine.routes.pyvista_accessor import pinn_mesh_hexa

    with pytest.raises(KeywordError, match=r"^pinn_mesh_hexa: unknown keyword siz=; did you"):
        pinn_mesh_hexa(pv.read(EXAMPLES / "hexa_bend.vtp"), siz=(5, 5, 5))


BAD_VALUES = [
    ({"size": (41.5, 21)}, r"^size=\(41.5, 21\): node counts are whole numbers, e.g. size="),
    ({"size": "41 21"}, r"^size='41 21': give the node counts as a tuple, e.g. size=\(41, 21"),
    ({"size": 41}, r"^size=41: give the node counts as a tuple"),
    ({"aux": 42}, r"^aux: expected a pyvista/VTK PolyData, an array of points or a list of th"),
]


@pytest.mark.parametrize(("keywords", "message"), BAD_VALUES)
def test_bad_values_are_refused_in_one_line(keywords, message):
    with pytest.raises(ValueError, match=message):
        pv.read(EXAMPLES / "fig2.vtp").pinn_mesh(method="tfi", **keywords)


def test_whole_floats_are_node_counts():
    grid = pv.read(EXAMPLES / "fig2.vtp").pinn_mesh(method="tfi", size=(11.0, np.int64(6)))
    assert grid.dimensions == (11, 6, 1)


def test_cgns_without_h5py_is_the_missing_extra_error(tmp_path, monkeypatch):
    from pinn_engine.io.export import cgns

    monkeypatch.setattr(cgns, "_H5PY", [None])
    monkeypatch.setenv("PINN_MESH_PYTHON", str(tmp_path / "nowhere"))
    grid = pv.read(EXAMPLES / "fig2.vtp").pinn_mesh(size=(11, 6), method="tfi")
    with pytest.raises(ImportError) as caught:
        pinn_engine.save(grid, tmp_path / "g.cgns")
    assert isinstance(caught.value, MissingExtraError)
    assert str(caught.value) == (
        "cgns: writing CGNS (h5py) needs the cgns extra: pip install 'pinn-mesh[cgns]'"
    )
    assert "helper Python" in str(caught.value.for_route("paraview"))
    assert not (tmp_path / "g.cgns").exists()


def test_the_manifest_error_is_a_pinn_mesh_error():
    from pinn_engine.batch import ManifestError

    assert issubclass(ManifestError, PinnMeshError) and issubclass(ManifestError, ValueError)


def test_a_multiblock_cgns_goes_through_the_helper_python(lshape, tmp_path, monkeypatch):
    """Where this Python's h5py is unusable (ParaView's), the helper Python writes every
    kind of CGNS, the multi-block zones with their joins too (here this venv's Python
    behind a wrapper script, so that it counts as another)."""
    import sys

    from pinn_engine.io.export import cgns

    helper = tmp_path / "python"
    helper.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    helper.chmod(0o755)
    direct = pinn_engine.save(lshape[1], tmp_path / "direct.cgns", extrude=0.1)
    monkeypatch.setenv("PINN_MESH_PYTHON", str(helper))
    monkeypatch.setattr(cgns, "_H5PY", [None])
    helped = pinn_engine.save(lshape[1], tmp_path / "helped.cgns", extrude=0.1)
    with h5py.File(direct, "r") as a, h5py.File(helped, "r") as b:
        names: list[str] = []
        a.visit(names.append)
        seen: list[str] = []
        b.visit(seen.append)
        assert seen == names and any("ZoneGridConnectivity/" in n for n in names)
        for name in names:
            if isinstance(a[name], h5py.Dataset):
                np.testing.assert_array_equal(a[name][()], b[name][()])
