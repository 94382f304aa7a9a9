"""Training only where the network can win: without a term the start leaves to win (lines
to follow, orthogonal sides, a spacing) the pinn's map is its start, decided before torch is
imported; the report says so and times each stage."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT, run_blocks

from pinn_engine import job
from pinn_engine.bodies.airfoil import circle, load_body
from pinn_engine.bodies.bodygrid import elliptic, layout
from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.body.mesh import mesh_body
from pinn_engine.kinds.body.untrained import (
    BODY_HELD_ROWS,
    THIN,
    THIN_WALL,
    WALL,
    body_cannot_win,
    body_start,
    held_rows,
    held_worst,
)
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.kinds.untrained import QUALITY, WINSLOW, cannot_win, start_or_train
from pinn_engine.settings import make_settings

NOTCH = EXAMPLES / "hard" / "notch_v_sharp.vtp"
SIZE = (21, 11)


def _assert_torch_not_imported(code: str) -> None:
    """Run ``code`` (which ends by printing whether torch is in sys.modules) in a fresh
    interpreter: it must not have imported torch."""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.stdout.strip() == "False", out.stderr


def test_one_sequence_keeps_the_start_or_trains_never_both():
    """``start_or_train``: with a reason the start is kept and the training (which would
    import torch) never called; without one the training's map is the result."""
    called = []

    def keep(reason: str) -> str:
        called.append(("keep", reason))
        return "start"

    def train() -> str:
        called.append(("train",))
        return "network"

    assert start_or_train(WINSLOW, keep, train) == "start" and called == [("keep", WINSLOW)]
    called.clear()
    assert start_or_train(None, keep, train) == "network" and called == [("train",)]


def test_the_decision_follows_the_terms_the_network_could_win():
    """Untrained under the default (the quality objective's start) with or without lines,
    and under the Winslow equations alone; trained under the Winslow equations with lines to
    follow, with orthogonal sides, a spacing, without the warm start, for mgnet, or with
    Adam epochs asked."""
    boundary = load_boundary(EXAMPLES / "fig2.vtp")
    lines = load_aux([EXAMPLES / "fig2_aux.vtp"], boundary)
    assert cannot_win(make_settings("pinn")) == QUALITY
    assert cannot_win(make_settings("pinn"), lines) == QUALITY
    assert cannot_win(make_settings("pinn", objective="quality"), lines) == QUALITY
    assert cannot_win(make_settings("pinn", objective="winslow")) == WINSLOW
    assert cannot_win(make_settings("pinn", objective="winslow"), lines) is None
    assert cannot_win(make_settings("pinn", orthogonal=("bottom",))) is None
    assert cannot_win(make_settings("pinn", spacing=(("bottom", 0.01),))) is None
    assert cannot_win(make_settings("pinn", "paper")) is None
    assert cannot_win(make_settings("mgnet")) is None
    assert cannot_win(make_settings("pinn", adam_epochs=60)) is None


def test_an_untrained_map_is_the_start_it_would_have_kept():
    """The untrained default's grid is the trained default's with no L-BFGS iteration (its
    start, to round-off), the report says why it was not trained, and torch stays out."""
    boundary = load_boundary(NOTCH)
    winslow = make_settings("pinn", lattice=SIZE, objective="winslow")
    skipped = Mesher(winslow).fit(boundary).predict(*SIZE)
    training = skipped.report["training"]
    assert training["skipped"] == WINSLOW and training["result"] == "start"
    forced = make_settings("pinn", lattice=SIZE, objective="winslow", lbfgs_iterations=0)
    from pinn_engine.classical.pins import pinned_boundary
    from pinn_engine.kinds.four_sided.problem import train
    from pinn_engine.starts.warmstart import lattice_for

    pinned = pinned_boundary(boundary, *lattice_for(*SIZE))  # as Mesher.fit pins its sides
    start = train(pinned, [], forced).grid(*SIZE)
    np.testing.assert_allclose(pinned.frame.to_unit(skipped.points), start, atol=1e-12)
    code = (
        "import sys; from pinn_engine.io.pipeline import load_boundary;"
        "from pinn_engine.kinds.four_sided.mesher import Mesher;"
        "from pinn_engine.settings import make_settings;"
        f"b = load_boundary({str(NOTCH)!r});"
        f"Mesher(make_settings('pinn', lattice={SIZE})).fit(b).predict(*{SIZE});"
        "print('torch' in sys.modules)"
    )
    _assert_torch_not_imported(code)


def test_a_multiblock_pinn_whose_networks_cannot_win_keeps_its_starts():
    """Without auxiliary lines every block keeps its start (the elliptic grid, as fine as
    the elliptic run's), the report says why and times the stages."""
    files = EXAMPLES / "lshape.vtp", [EXAMPLES / "lshape_blocks.vtp"]
    runs = {m: run_blocks(make_settings(m, cell_size=0.1), *files) for m in ("elliptic", "pinn")}
    for ell, pinn in zip(runs["elliptic"].grids, runs["pinn"].grids):
        assert np.array_equal(ell, pinn)
    report = runs["pinn"].report
    assert {b["skipped"] for b in report["training"]["blocks"]} == {WINSLOW}
    assert set(report["timings"]) == {"layout", "solve", "training", "walls_and_quality"}
    assert 0 < sum(report["timings"].values()) <= report["mesh_seconds"] + 1e-9


def test_a_body_network_is_trained_only_where_its_wall_cells_are_not_too_thin():
    """Untrained on a boundary-layer grid (wall cells of aspect ratio THIN_WALL or more) and
    under the default objective; trained on coarser wall cells under --objective winslow,
    without the elliptic start, or with Adam epochs asked."""
    assert body_cannot_win(make_settings("pinn"), THIN_WALL) == THIN
    assert body_cannot_win(make_settings("pinn"), THIN_WALL / 2) == WALL  # the default
    assert body_cannot_win(make_settings("pinn", objective="winslow"), THIN_WALL / 2) is None
    assert body_cannot_win(make_settings("pinn", "paper"), 10 * THIN_WALL) is None
    assert body_cannot_win(make_settings("pinn", adam_epochs=60), 10 * THIN_WALL) is None


@pytest.mark.slow
def test_an_untrained_body_grid_is_the_start_its_trained_network_kept():
    """On a small NACA 0012 C-grid with a first layer of 1e-5 chord the trained network's
    guard keeps the elliptic start; the untrained run (the Winslow objective: the default
    also optimises the nodes off the first layer) writes that grid bit for bit, says why,
    times its stages and imports no torch."""
    body = load_body(naca="0012")
    far, size, wall = circle(body, 12), (97, 25), 1e-5
    settings = make_settings("pinn", lattice=size, lbfgs_points=200)
    winslow = make_settings("pinn", lattice=size, lbfgs_points=200, objective="winslow")
    skipped = mesh_body(body, far, "c", "pinn", *size, winslow, wall_spacing=wall)
    from pinn_engine.kinds.body.problem import train_body

    lay = layout(body, far, "c", *size, wall_spacing=wall)
    trained, _, info = train_body(lay, *elliptic(lay), settings)
    assert info["result"] == "start" and info["lbfgs_iterations"] > 0
    assert np.array_equal(skipped.points, trained)
    report = skipped.report
    assert report["training"]["skipped"] == THIN
    assert set(report["timings"]) == {"layout", "elliptic", "start", "training", "quality"}
    assert report["timings"]["training"] == report["train_seconds"] == 0.0  # none trained
    code = (
        "import sys; from pinn_engine.bodies.airfoil import circle, load_body;"
        "from pinn_engine.kinds.body.mesh import mesh_body; b = load_body(naca='0012');"
        f"mesh_body(b, circle(b, 12), 'c', 'pinn', *{size}, wall_spacing={wall});"
        "print('torch' in sys.modules)"
    )
    _assert_torch_not_imported(code)
    coarse = layout(body, far, "c", *size)  # the default first layer: cells of aspect 2
    assert body_cannot_win(settings, coarse.wall_aspect()) == WALL
    winslow = make_settings("pinn", lattice=size, objective="winslow")
    assert body_cannot_win(winslow, coarse.wall_aspect()) is None


def test_a_hexahedral_pinn_whose_network_cannot_win_keeps_its_start(tmp_path):
    """Without a spacing or orthogonal patch the six-faced pinn's map is the elliptic run's
    grid, untrained and without torch; the report says why and times the stages."""
    surface = EXAMPLES / "hexa_bump_box.vtp"
    size = (7, 6, 5)
    runs = {
        m: mesh_surface(str(surface), make_settings(m, size=size)) for m in ("elliptic", "pinn")
    }
    np.testing.assert_allclose(runs["pinn"].grid, runs["elliptic"].grid, atol=1e-12)
    assert runs["pinn"].model.info["skipped"] == WINSLOW
    written = tmp_path / "r.json"
    code = (
        "import sys, json; from pinn_engine.routes.cli import main;"
        f"main([{str(surface)!r}, '--size', '7', '6', '5', '-o', {str(tmp_path / 'g.vts')!r},"
        f" '--report', {str(written)!r}, '--quiet']);"
        "print('torch' in sys.modules)"
    )
    _assert_torch_not_imported(code)
    report = json.loads(written.read_text())
    assert report["training"]["skipped"] == WINSLOW
    assert set(report["timings"]) >= {"read", "faces", "start", "training", "quality", "write"}


@pytest.mark.parametrize("topology", ["o", "c"])
def test_the_default_body_grid_has_a_lower_worst_cell_with_the_wall_rows_kept(topology):
    """The NACA 0012 O- and C-grids at the default size: the default returns the elliptic
    grid with its nodes off the first layer optimised, whose worst cell is below the elliptic
    grid's and mean no higher, with the wall's and the first layer's rows (first edges, wall
    angles) and the seam or cut as the elliptic grid's; nothing trained. (The command's
    sections: an O-grid's with a blunt trailing edge, a C-grid's closed.)"""
    body = load_body(naca="0012", te="blunt" if topology == "o" else "sharp")
    far, size = circle(body, 15), (41, 21)
    runs = {m: mesh_body(body, far, topology, m, *size) for m in ("elliptic", "pinn")}
    ell, best = runs["elliptic"], runs["pinn"]
    assert best.report["quality"]["worst_max_angle"] < ell.report["quality"]["worst_max_angle"]
    assert best.report["quality"]["mean_max_angle"] <= ell.report["quality"]["mean_max_angle"]
    assert best.report["quality"]["folded_cells"] == 0
    np.testing.assert_array_equal(best.points[:2], ell.points[:2])
    np.testing.assert_array_equal(best.points[-1], ell.points[-1])
    gap = "seam_gap" if topology == "o" else "cut_gap"
    assert best.report["topology"][gap] == 0.0
    assert best.report["topology"]["wall_angle_deviation"] < 1e-3
    assert best.report["training"]["start"] == "optimized"
    assert best.report["train_seconds"] == 0.0
    assert best.report["choice"].startswith("chose the optimized grid")


def _default_c_grid(method: str):
    """The command's C-grid of ``example_data/naca0012.dat`` at the default size and first
    layer (a boundary layer: wall cells of aspect ratio far above ``LAYER_ASPECT``)."""
    settings = make_settings(method, topology="c")
    return job.run(settings, job.geometry_from_files(settings, EXAMPLES / "naca0012.dat"))


def test_the_default_c_grid_is_optimised_beyond_its_boundary_layer():
    """That C-grid's first layer is thin (aspect far above 20), so its boundary
    layer's rows are held and the nodes beyond them optimised: the worst cell below the
    elliptic grid's, the held rows and far field the elliptic grid's to the bit, the wall
    angles 90 degrees, and no training second."""
    ell, best = _default_c_grid("elliptic"), _default_c_grid("pinn")
    e, b = ell.grids[0], best.grids[0]
    held = held_rows(e)
    assert held > BODY_HELD_ROWS
    assert best.report["quality"]["worst_max_angle"] < ell.report["quality"]["worst_max_angle"]
    assert best.report["training"]["start"] == "optimized"
    np.testing.assert_array_equal(b[:held], e[:held])
    np.testing.assert_array_equal(b[-1], e[-1])
    assert best.report["topology"]["wall_angle_deviation"] < 1e-3
    assert best.report["train_seconds"] == 0.0


def test_no_optimisation_where_the_worst_cell_is_in_the_held_rows(monkeypatch):
    """A body grid whose worst cell lies between its held rows is kept as it is, without
    the optimisation (which could not lower that cell) being run."""
    nj, ni = 12, 30
    i, j = np.meshgrid(np.linspace(0.0, 1.0, ni), np.geomspace(1e-4, 1.0, nj) - 1e-4)
    grid = np.stack([i, j], axis=-1)
    assert held_rows(grid) > BODY_HELD_ROWS  # rows of cells 1e-4 high, 0.03 wide
    grid[1, ni // 2, 0] += 0.02  # a sheared cell next to the wall
    assert held_worst(grid, held_rows(grid)) > held_worst(grid[held_rows(grid) - 1 :])
    from pinn_engine.starts import quality_start

    monkeypatch.setattr(quality_start, "body_quality_start", None)  # any call fails
    kept, training = body_start(grid, THIN, True, False)
    assert kept is grid and training["start"] == "elliptic"
