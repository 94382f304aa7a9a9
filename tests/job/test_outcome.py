"""One job for every domain kind: ``job.kind_of`` names the kind of a run's inputs, each
kind's adapters (from files, from VTK data) give the same geometry, and ``job.run`` gives one
``Outcome`` whose nodes are its VTK data's, in VTK's index order."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

from pinn_engine import job
from pinn_engine.errors import InputError
from pinn_engine.io.fileio import read_polydata
from pinn_engine.settings import make_settings

FIG2, BEND = EXAMPLES / "fig2.vtp", EXAMPLES / "hexa_bend.vtp"
LSHAPE, LSHAPE_EDGES = EXAMPLES / "lshape.vtp", EXAMPLES / "lshape_blocks.vtp"
PIPE = EXAMPLES / "blockmesh" / "pipe" / "system" / "blockMeshDict"


def _geometries(kind: str):
    """The settings of a small tfi run of ``kind``, and its geometry from files and from VTK
    data."""
    if kind == "four-sided":
        settings = make_settings("tfi", size=(9, 5), lattice=(9, 5))
        files = job.geometry_from_files(settings, FIG2)
        data = job.geometry_from_polydata(settings, [read_polydata(FIG2)])
    elif kind == "body":
        settings = make_settings("tfi", size=(17, 9), topology="o", naca="0012")
        files = job.geometry_from_files(settings, None)
        data = job.geometry_from_polydata(settings, [])
    elif kind == "blocks":
        settings = make_settings("tfi", cell_size=0.25)
        files = job.blocks_from_files(LSHAPE, [LSHAPE_EDGES])
        data = job.blocks_from_polydata([read_polydata(LSHAPE)], [read_polydata(LSHAPE_EDGES)])
    elif kind == "dictionary":
        settings = make_settings("tfi")
        files = job.dictionary_from_file(PIPE)
        data = job.dictionary_from_text(PIPE.read_text())
    else:
        settings = make_settings("tfi", size=(7, 6, 5))
        files = job.hexa_from_file(BEND)
        data = job.hexa_from_polydata(read_polydata(BEND))
    return settings, files, data


def _points(grid) -> np.ndarray:
    """A structured grid's points (n, 3)."""
    return vtk_to_numpy(grid.GetPoints().GetData())


@pytest.mark.parametrize(
    ("boundary", "options", "kind"),
    [
        (FIG2, {}, "four-sided"),
        (FIG2, {"body": True}, "body"),
        (Path("naca.dat"), {}, "body"),
        (LSHAPE, {"blocks": True}, "blocks"),
        (FIG2, {"size": (5, 5, 5)}, "hexa"),
        (BEND, {}, "hexa"),
        (EXAMPLES / "hexa_bend.stl", {}, "hexa"),
        (PIPE, {}, "dictionary"),
    ],
)
def test_kind_of_names_each_kind_from_files_and_data(boundary, options, kind):
    """A file's kind, and its data's (an STL's triangles carry no FaceId: three sizes name
    them)."""
    assert job.kind_of(boundary, **options) == kind
    if boundary.exists() and boundary.suffix not in (".stl", ""):
        assert job.kind_of(read_polydata(boundary), **options) == kind


@pytest.mark.parametrize("kind", job.KINDS)
def test_every_kind_gives_one_outcome_in_one_index_order(kind):
    """From files and from VTK data alike: the kind's Outcome, each block's nodes those of
    its VTK data in VTK's order (i fastest), the report's quality over all its cells."""
    settings, files, data = _geometries(kind)
    outcome = job.run(settings, files)
    assert outcome.kind == kind and not outcome.trained
    blocks = outcome.data
    if isinstance(blocks, vtkMultiBlockDataSet):
        blocks = [blocks.GetBlock(k) for k in range(blocks.GetNumberOfBlocks())]
    else:
        blocks = [blocks]
    assert len(blocks) == len(outcome.grids) > 0
    cells = 0
    for grid, nodes in zip(blocks, outcome.grids, strict=True):
        extent = grid.GetExtent()
        dims = [extent[2 * a + 1] - extent[2 * a] + 1 for a in range(3)]
        assert nodes.shape[:-1] == tuple(n for n in dims[::-1] if n > 1)
        dim = nodes.shape[-1]
        np.testing.assert_allclose(_points(grid)[:, :dim], nodes.reshape(-1, dim), atol=1e-12)
        cells += grid.GetNumberOfCells()
    assert outcome.report["quality"]["folded_cells"] == 0 and outcome.quality["mean_max_angle"]
    assert outcome.report.get("cells", cells) == cells
    again = job.run(settings, data)
    for a, b in zip(outcome.grids, again.grids, strict=True):
        np.testing.assert_allclose(a, b, atol=1e-12)


@pytest.mark.parametrize("kind", job.KINDS)
def test_the_registry_holds_every_kind_and_refuses_what_it_does_not_take(kind, tmp_path):
    """Each kind's geometry finds its one registry entry, which names the kind; a family
    model or a field is refused, before meshing, by a kind that does not take it."""
    settings, files, _ = _geometries(kind)
    entry = job.kind_of_geometry(files)
    assert kind in entry.names and [k for k in job.REGISTRY if kind in k.names] == [entry]
    if not entry.family:
        with pytest.raises(InputError, match="mesh without the model"):
            job.run(settings, files, family=tmp_path / "none.family")
    if not entry.adapts:
        with pytest.raises(ValueError, match="applies to 2D domains"):
            job.run(settings, files, field=object())


def test_the_registry_points_at_the_kinds_packages():
    """Each registry entry's geometry (with its adapters and run) is a kind's, in ``kinds/``:
    a package of its own, or ``kinds.single`` for the four-sided domain and the body, which
    share one geometry; every package of ``kinds/`` is reached by one entry."""
    packages = {p.parent.name for p in (ROOT / "pinn_engine" / "kinds").glob("*/__init__.py")}
    reached = set()
    for entry in job.REGISTRY:
        home = entry.geometry.__module__.split(".")
        assert home[:2] == ["pinn_engine", "kinds"], entry
        if home[2] == "single":
            reached |= {name.replace("-", "_") for name in entry.names}
        else:
            reached.add(home[2])
    assert reached == packages
