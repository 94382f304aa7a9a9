"""The least non-orthogonal section of a swept blocking (SPEC 15): its figures are
checkMesh's of the 3D grid, its gradient the figures', and on a butterfly pipe whose Winslow
grid is more skewed than blockMesh's it is far less non-orthogonal with no more skewness."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from helpers import EXAMPLES

from pinn_engine.blocks3d import section as S
from pinn_engine.blocks3d.checks import figures, hexes
from pinn_engine.blocks3d.dictionary import from_text
from pinn_engine.blocks3d.mesh import ORTHOGONAL, mesh_dictionary, winslow_grid
from pinn_engine.blocks3d.placement import place
from pinn_engine.blocks3d.winslow import boundary_held, winslow
from pinn_engine.hexa.inexact import InexactSolve

sys.path.insert(0, str(EXAMPLES / "blockmesh"))
from make_dictionaries import pipe  # noqa: E402


def bulging_pipe() -> str:
    """A butterfly pipe whose centre square (0.4 radii) has edges bulging 1.15 times out and
    no grading: the Winslow grid's star points are more skewed than blockMesh's."""
    return pipe(square=0.4, grade=1, bulge=1.15, cells=(6, 5, 2))


def swept_pipe():
    placed = place(from_text(bulging_pipe()))
    return placed, S.section(placed, boundary_held(placed)[1])


def test_the_section_figures_are_checkmesh_figures_of_the_swept_grid():
    """Nodes moved at random in the section (every layer alike): the section's largest
    non-orthogonality and skewness are the 3D grid's, to round-off."""
    placed, sec = swept_pipe()
    assert sec.axis == 2 and len(sec.quads) == 6 * 6 + 4 * 6 * 5
    xy = S.start_of(placed.points, sec)
    moved = xy + 2e-4 * np.random.default_rng(1).normal(size=xy.shape) * sec.free
    angle, skew, turn = S.figures(moved, sec)
    cells = np.vstack([hexes(ids) for ids in placed.ids])
    got = figures(S.swept(placed.points, sec, moved), cells)
    assert turn.min() > 0 and got.folded == 0
    assert angle.max() == pytest.approx(got.max_non_orthogonality, abs=1e-9)
    assert skew.max() == pytest.approx(got.max_skewness, abs=1e-9)


def test_the_objective_gradient_is_its_derivative():
    """The hand-written gradient against central differences, with the skewness penalty
    active (a bound under the grid's skewness)."""
    placed, sec = swept_pipe()
    xy = S.start_of(placed.points, sec)
    bound = 0.5 * S.figures(xy, sec)[1].max()
    value, grad = S.objective(xy, sec, bound)[:2]
    step = 1e-7
    for seed in range(3):
        direction = np.random.default_rng(seed).normal(size=xy.shape) * sec.free
        ahead = S.objective(xy + step * direction, sec, bound)[0]
        behind = S.objective(xy - step * direction, sec, bound)[0]
        assert (ahead - behind) / (2 * step) == pytest.approx((grad * direction).sum(), rel=1e-5)


def test_a_blocking_that_is_no_swept_section_has_none():
    box = """
    vertices ( (0 0 0) (2 0 0) (2 1 0) (0 1 0) (0 0 0.5) (2 0 0.5) (2.2 1.1 0.6) (0 1 0.5) );
    blocks ( hex (0 1 2 3 4 5 6 7) (4 4 2) simpleGrading (1 1 1) );
    """
    placed = place(from_text(box))
    assert S.section(placed, boundary_held(placed)[1]) is None


def test_the_default_optimises_a_pipe_whose_winslow_grid_is_more_skewed():
    """The Winslow grid's star points leave it more skewed than blockMesh's placement, so
    it cannot be kept; the optimised section is at least 5 degrees less non-orthogonal than
    blockMesh's with no more skewness and no fold, the wall still on the cylinder."""
    result = mesh_dictionary(from_text(bulging_pipe()))
    tfi, ell = result.candidates["tfi"], result.candidates["elliptic"]
    assert ell.max_skewness > tfi.max_skewness
    assert result.kept == "optimised" and result.report["start"] == "tfi"
    kept = figures(result.points, result.cells)
    assert kept.folded == 0  # the figures measured on the slab, to round-off
    assert kept.as_dict() == pytest.approx(result.candidates["optimised"].as_dict(), abs=1e-9)
    assert kept.max_skewness <= tfi.max_skewness
    assert kept.max_non_orthogonality < tfi.max_non_orthogonality - 5
    wall = np.unique(result.place.patches[2][2])
    assert np.allclose(np.hypot(*result.points[wall, :2].T), 0.05)


def test_the_section_search_also_begins_from_blockmeshs_placement():
    """A butterfly pipe whose centre square is 0.6 radii: the search from the grid chosen
    (a blend towards the Winslow grid, whose smooth cells sit in a basin of their own) and
    from blockMesh's placement; the placement's wins, under 5 degrees with a mean below
    blockMesh's (the Winslow grid's mean is above it)."""
    result = mesh_dictionary(from_text(pipe(square=0.6, cells=(8, 6, 2))))
    tfi, ell = result.candidates["tfi"], result.candidates["elliptic"]
    assert ell.mean_non_orthogonality > tfi.mean_non_orthogonality
    assert result.kept == "optimised" and result.report["start"] == "tfi"
    kept = result.candidates["optimised"]
    assert kept.folded == 0 and kept.max_skewness <= tfi.max_skewness
    assert kept.max_non_orthogonality < 5
    assert kept.mean_non_orthogonality < tfi.mean_non_orthogonality


def test_a_swept_section_is_solved_as_its_slab():
    """A pipe four blocks along its axis (a section of 5 blocks in 4 layers of blocks): the
    Winslow grid is its slab's, one cell thick, swept (every layer the same), and it solves
    the 3D equations as the grid solved over every layer does."""
    placed = place(from_text(pipe(square=0.4, grade=1, bulge=1.15, cells=(6, 5, 8), layers=4)))
    sec = S.section(placed, boundary_held(placed)[1])
    slab = S.slab(placed, sec)
    assert len(slab.ids) == 5 and len(slab.points) == 2 * len(sec.nodes)
    got, _ = winslow_grid(placed, sec)
    assert np.array_equal(got[:, sec.plane], got[sec.nodes[sec.column]][:, sec.plane])
    cells = np.vstack([hexes(ids) for ids in placed.ids])
    whole, swept = figures(winslow(placed)[0], cells), figures(got, cells)
    assert swept.folded == 0
    assert swept.max_non_orthogonality == pytest.approx(whole.max_non_orthogonality, abs=0.05)
    assert swept.max_skewness == pytest.approx(whole.max_skewness, abs=0.005)


def test_no_second_search_follows_one_that_reaches_orthogonal(monkeypatch):
    """The search from the Winslow grid reaches a section within ``ORTHOGONAL`` of
    orthogonal: the search from blockMesh's placement could gain less, so it is not run."""
    searches = []

    def counted(*args):
        searches.append(args)
        return least(*args)

    least = S.least_non_orthogonal
    monkeypatch.setattr(S, "least_non_orthogonal", counted)
    result = mesh_dictionary(from_text(pipe(cells=(6, 5, 2))))
    assert result.kept == "optimised" and result.start == "elliptic" and len(searches) == 1
    assert result.candidates["optimised"].max_non_orthogonality <= ORTHOGONAL


def test_a_swept_grids_figures_are_its_slabs_counted_over_its_layers():
    """checkMesh's figures of swept grids (blockMesh's placement, one with its section
    moved at random) measured on the slab and counted over the layers are those measured on
    every cell, to round-off; a quadrilateral folded folds its column's cells."""
    placed = place(from_text(pipe(square=0.4, grade=1, bulge=1.15, cells=(6, 5, 8), layers=4)))
    sec = S.section(placed, boundary_held(placed)[1])
    slab = S.SlabFigures(placed, sec, 8)
    cells = np.vstack([hexes(ids) for ids in placed.ids])
    xy = S.start_of(placed.points, sec)
    moved = xy + 2e-4 * np.random.default_rng(2).normal(size=xy.shape) * sec.free
    inside = int(np.flatnonzero(sec.free.all(axis=1))[0])
    folded = xy.copy()
    folded[inside] = xy[sec.quads[np.any(sec.quads == inside, axis=1)][0]].sum(0) - 3 * xy[inside]
    for grid in (xy, moved):
        points = S.swept(placed.points, sec, grid)
        got, want = slab(points), figures(points, cells)
        assert got.max_non_orthogonality == pytest.approx(want.max_non_orthogonality, abs=1e-9)
        assert got.mean_non_orthogonality == pytest.approx(want.mean_non_orthogonality, abs=1e-6)
        assert got.max_skewness == pytest.approx(want.max_skewness, abs=1e-9)
        assert got.folded == want.folded == 0
    points = S.swept(placed.points, sec, folded)
    assert slab(points).folded == figures(points, cells).folded > 0


def test_a_slab_solves_one_face_and_its_twin_moves_with_it(monkeypatch):
    """The slab's back face mirrors its front (``twin``): the systems have the front face's
    rows alone, half the unknowns, and the grid is the slab's solved over both faces (this
    small one's systems are solved exactly: to round-off), both faces the same in-plane."""
    placed, sec = swept_pipe()
    slab, n = S.slab(placed, sec), len(sec.nodes)
    sizes = []
    solve = InexactSolve.solve

    def counted(self, mat, rhs):
        sizes.append(mat.shape[0])
        return solve(self, mat, rhs)

    monkeypatch.setattr(InexactSolve, "solve", counted)
    both, _ = winslow(slab)
    unknowns, sizes[:] = sizes[0], []
    one, _ = winslow(slab, twin=np.tile(np.arange(n), 2))
    assert 2 * sizes[0] == unknowns
    assert np.array_equal(one[:n, sec.plane], one[n:, sec.plane])
    assert np.abs(one - both).max() < 1e-12 * np.ptp(slab.points, axis=0).max()
