"""Multi-block family models (SPEC 16): a cylinder-in-channel blocking with the cylinder moved
and resized; the round trip (fit, save, load, mesh), the guard's fallback to the member's own
run, and a member of another blocking refused in one line."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine import job
from pinn_engine.errors import InputError
from pinn_engine.family import mesh as family_mesh
from pinn_engine.multiblock.chains import parse_cells
from pinn_engine.settings import make_settings

sys.path.insert(0, str(EXAMPLES))  # make_multiblock: the DFG channel's rings and block edges
from make_multiblock import DFG_BOX as BOX  # noqa: E402
from make_multiblock import DFG_HEIGHT as HEIGHT  # noqa: E402
from make_multiblock import DFG_LENGTH as LENGTH  # noqa: E402
from make_multiblock import dfg  # noqa: E402

SETTINGS = make_settings("pinn", kind="blocks")
# (centre x, centre y, radius) of the training members: about the ranges' corners and centre
TRAIN = [(0.18, 0.17, 0.04), (0.26, 0.17, 0.06), (0.18, 0.24, 0.06), (0.26, 0.24, 0.04)]
TRAIN += [(0.22, 0.205, 0.05)]


def cylinder(cx: float, cy: float, r: float, split: bool = False) -> job.BlocksGeometry:
    """The channel with a cylinder at (cx, cy) of radius ``r``: a square round it cut along
    its diagonals and its sides carried on to the walls, the inlet and the outlet (with
    ``split``, the blocks downstream cut across at mid-channel too: another blocking); every
    chain's cells fixed (as a family's counts are)."""
    (channel, hole), edges = dfg((cx, cy), r)
    y0, y1 = cy - BOX, cy + BOX
    if split:  # three edges across, each ending on the channel or on an edge along it
        across = [0.0, y0, y1, HEIGHT]
        edges += [np.array([(LENGTH / 2, a), (LENGTH / 2, b)]) for a, b in zip(across, across[1:])]
    out = 0.5 * (r + BOX * np.sqrt(2)) / np.sqrt(2)
    places = [(0.005, 0, 4), (cx, 0, 8), (LENGTH - 0.005, 0, 16), (0, 0.005, 4), (0, cy, 8)]
    places += [(cx, HEIGHT, 8), (LENGTH, cy, 8), (0, HEIGHT - 0.005, 4), (cx + out, cy + out, 5)]
    cells = parse_cells([f"{x},{y}={n}" for x, y, n in places])
    names = [f"edge {k}" for k in range(len(edges))]
    return job.BlocksGeometry([channel, hole], edges, names, "cylinder", cells=tuple(cells))


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A model fitted on the eight training members, saved."""
    runs = [job.member_run(SETTINGS, cylinder(*p)) for p in TRAIN]
    members = [member for _, member in runs]
    targets = [job.member_target(member, outcome) for outcome, member in runs]
    model = job.fit_family_model(members, targets)
    path = tmp_path_factory.mktemp("family") / "cylinder.pt"
    model.save(path)
    return path


def _boundary_nodes(outcome, ring) -> np.ndarray:
    """The nodes of ``outcome``'s blocks that lie on ``ring``, sorted."""
    from pinn_engine.geometry.boundary import segment_distance

    nodes = np.unique(np.vstack([g.reshape(-1, 2) for g in outcome.grids]), axis=0)
    return nodes[segment_distance(nodes, ring) < 1e-12]


def test_a_saved_multiblock_model_meshes_a_new_member_within_its_own_runs_bounds(fitted):
    """The round trip: the loaded model's grid of an unseen member (another centre and
    radius) has the own run's nodes on the cylinder exactly and as many on the channel's
    walls, inlet and outlet (those beside the sliding edge ends placed by the model's ends,
    within 0.5 % of the channel's length of the own run's), no fold and the own grid's
    quality (worst within 2 degrees, mean within 0.5); the report says family and names the
    model's file, and so do the blocks' field data."""
    g = cylinder(0.22, 0.2, 0.05)
    own = job.run(SETTINGS, g)
    fam = job.run(SETTINGS, g, family=str(fitted))
    family = fam.report["family"]
    assert family["result"] == "family" and family["model"] == str(fitted)
    q, d = fam.quality, own.quality
    assert q["folded_cells"] == 0
    assert q["worst_max_angle"] <= d["worst_max_angle"] + 2.0
    assert q["mean_max_angle"] <= d["mean_max_angle"] + 0.5
    assert len(fam.grids) == len(own.grids) == 12
    outer, hole = g.rings
    np.testing.assert_array_equal(_boundary_nodes(fam, hole), _boundary_nodes(own, hole))
    ours, theirs = _boundary_nodes(fam, outer), _boundary_nodes(own, outer)
    assert len(ours) == len(theirs)
    moved = np.linalg.norm(ours[:, None] - theirs[None], axis=2).min(axis=1)
    assert moved.max() < 0.005 * LENGTH
    block = fam.data.GetBlock(0).GetFieldData()
    assert block.GetAbstractArray("NetworkResult").GetValue(0) == "family"
    assert block.GetAbstractArray("FamilyModel").GetValue(0) == str(fitted)


def test_a_folded_multiblock_prediction_falls_back_to_the_members_own_run(fitted, monkeypatch):
    """Where the model's grid folds a cell the member's own run is solved from its layout:
    the grid is the own run's exactly, and the report says start and why."""
    g = cylinder(0.22, 0.2, 0.05)
    own = job.run(SETTINGS, g)
    real = family_mesh.FamilyModel.predict

    def folded(self, member):
        grid, info = real(self, member)
        blocks = member.blocks_of(grid)
        blocks[2][2, 2], blocks[2][2, 3] = blocks[2][2, 3].copy(), blocks[2][2, 2].copy()
        return np.concatenate([b.reshape(-1, 2) for b in blocks]), info

    monkeypatch.setattr(family_mesh.FamilyModel, "predict", folded)
    fam = job.run(SETTINGS, g, family=str(fitted))
    assert fam.report["family"]["result"] == "start"
    assert "folded" in fam.report["family"]["fallback"]
    for a, b in zip(fam.grids, own.grids):
        np.testing.assert_array_equal(a, b)


def test_a_member_of_another_blocking_is_one_line(fitted):
    """A member whose blocking has another topology (15 blocks, not 12) is refused in one
    line naming both blockings."""
    with pytest.raises(InputError) as err:
        job.run(SETTINGS, cylinder(0.22, 0.2, 0.05, split=True), family=str(fitted))
    message = str(err.value)
    assert "\n" not in message and "outside the family" in message and "blocking" in message


def test_a_multiblock_member_with_auxiliary_lines_or_spacing_is_refused(fitted):
    """Options that place a multi-block member's nodes otherwise than its blocking's solve
    are refused in one line naming them."""
    from pinn_engine.multiblock.walls import parse_walls

    g = cylinder(0.22, 0.2, 0.05)
    g.walls = parse_walls(["boundary=0.001"], [])
    with pytest.raises(InputError, match="without --aux, --spacing"):
        job.run(SETTINGS, g, family=str(fitted))


def test_a_grid_below_the_members_tfi_start_keeps_the_start(fitted, monkeypatch):
    """Where the member's own choice keeps its start (its blocks' TFI grid ranks above the
    grid solved from the model's nodes), the report says start and why."""
    from pinn_engine.multiblock import mesh as multiblock_mesh

    monkeypatch.setattr(multiblock_mesh, "_tfi_ranks_better", lambda *args: True)
    fam = job.run(SETTINGS, cylinder(0.22, 0.2, 0.05), family=str(fitted))
    assert fam.report["family"]["result"] == "start"
    assert "TFI grid" in fam.report["family"]["fallback"]


def _route_inputs(g: job.BlocksGeometry) -> tuple[pv.PolyData, list[np.ndarray], dict]:
    """``g`` as the pyvista and ParaView routes take it: its rings as closed polylines in
    one PolyData, its block edges and its cells by place (``{(x, y): n}``)."""
    rings = [np.column_stack([ring, np.zeros(len(ring))]) for ring in g.rings]
    lines, start = [], 0
    for ring in rings:
        lines += [len(ring) + 1, *range(start, start + len(ring)), start]
        start += len(ring)
    boundary = pv.PolyData(np.vstack(rings), lines=lines)
    return boundary, list(g.edges), {(c.x, c.y): int(c.value) for c in g.cells}


def test_pyvista_meshes_a_multiblock_member_by_its_family_model(fitted):
    """pyvista's ``blocks=`` with ``model=``: the model's grid of the member, which its
    blocks' field data and the report name as the command line's do."""
    from pinn_engine import report

    boundary, edges, cells = _route_inputs(cylinder(0.22, 0.2, 0.05))
    blocks = boundary.pinn_mesh(blocks=edges, cells=cells, model=str(fitted))
    assert blocks.n_blocks == 12
    assert report(blocks)["family"]["result"] == "family"
    fields = blocks["block0"].field_data
    assert fields["NetworkResult"][0] == "family" and fields["FamilyModel"][0] == str(fitted)


def test_the_multiblock_filters_model_property_reaches_its_run(fitted):
    """The multi-block filter's Model (the panel's property, through the plain VTK
    algorithm) meshes by the model: a member of another blocking is its one-line refusal."""
    from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
    from pinn_engine.routes.panel import PANELS

    boundary, edges, cells = _route_inputs(cylinder(0.22, 0.2, 0.05, split=True))
    alg = PinnMultiBlockAlgorithm(route="pyvista")
    alg.SetInputDataObject(0, boundary)
    for edge in edges:
        alg.AddInputDataObject(1, pv.lines_from_points(np.column_stack([edge, [0, 0]])))
    alg.SetCells(cells)
    (model,) = [prop for prop in PANELS["blocks"] if prop.name == "Model"]
    getattr(alg, model.call)(model.convert(str(fitted)))
    assert alg.GetModel() == str(fitted)
    alg.Update()
    assert "outside the family" in alg.GetLastError() and "\n" not in alg.GetLastError()
    getattr(alg, model.call)(model.convert(""))
    assert alg.GetModel() is None


def test_a_multiblock_members_fallback_is_a_warning_on_every_route(fitted, monkeypatch):
    """A multi-block member whose model grid is not kept warns as a four-sided one does:
    pyvista's ``FamilyFallbackWarning``, the filter's warning line, the report's words."""
    from pinn_engine import report
    from pinn_engine.errors import FamilyFallbackWarning, family_fallback_warning
    from pinn_engine.multiblock import mesh as multiblock_mesh
    from pinn_engine.routes.filters import update_warning

    monkeypatch.setattr(multiblock_mesh, "_tfi_ranks_better", lambda *args: True)
    boundary, edges, cells = _route_inputs(cylinder(0.22, 0.2, 0.05))
    with pytest.warns(FamilyFallbackWarning, match="TFI grid"):
        blocks = boundary.pinn_mesh(blocks=edges, cells=cells, model=str(fitted))
    text = family_fallback_warning(report(blocks), "paraview")
    assert text and text in update_warning(report(blocks), "paraview", "")
