"""Real airfoil files (SPEC 9): crossing surfaces cut, never inside-out, Lednicer
without its count line, no stray warnings, refusal advice that works, real files clean."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from helpers import ROOT

from pinn_engine.bodies.airfoil import (
    body_from_points,
    circle,
    inside_polygon,
    load_body,
    naca4,
    read_dat,
)
from pinn_engine.errors import InputError, grid_warnings
from pinn_engine.kinds.body.mesh import mesh_body

# The real set is fetched data, kept in the checkout's shared/ and never committed.
AIRFOILS = ROOT / "shared" / "airfoils"
real_files = pytest.mark.skipif(
    not AIRFOILS.is_dir(), reason="the real airfoil set (shared/airfoils, not committed) is absent"
)


def _inside_out(r) -> int:
    """Nodes of the first row off the wall that lie inside the body."""
    n_w = r.report["topology"]["wake_nodes"]
    ni = r.points.shape[1]
    wall, row = r.points[0][n_w : ni - n_w], r.points[1][n_w : ni - n_w]
    return int(inside_polygon(row, wall[:-1] if n_w == 0 else wall).sum())


def _crossing_cusp() -> np.ndarray:
    """NACA 2412 whose surfaces are bent across each other over the last 20 % of the
    chord: the last point lies above the first (as RAE 2822's and NLF(1)-0416's files)."""
    xy = naca4("2412", 61)
    upper = np.arange(len(xy)) <= len(xy) // 2
    bend = 0.004 * np.clip((xy[:, 0] - 0.8) / 0.2, 0.0, 1.0) ** 2
    xy[:, 1] += np.where(upper, -bend, bend)
    return xy


def test_crossing_surfaces_are_cut_at_the_crossing_and_reported():
    xy = _crossing_cusp()
    assert xy[-1, 1] > xy[0, 1]  # the surfaces cross
    body = body_from_points(xy, "cusp")
    assert body.cut is not None and body.sharp
    assert 0.9 < body.cut[0] < 1.0  # at the crossing, ahead of the drawn trailing edge
    assert np.allclose(body.surface[0], body.cut) and np.allclose(body.surface[-1], body.cut)
    r = mesh_body(body, circle(body, 15), "o", "elliptic", 97, 25, wall_spacing=1e-4)
    assert r.report["topology"]["cut"] == pytest.approx(list(body.cut))
    texts = [text for text, _ in grid_warnings(r.report, "cli")]
    assert any("cut at the crossing" in t for t in texts)
    assert _inside_out(r) == 0 and r.quality["folded_cells"] == 0


def test_surfaces_that_do_not_cross_are_not_cut():
    assert body_from_points(naca4("2412", 61), "naca").cut is None


@pytest.mark.parametrize("topology", ["o", "c"])
def test_a_crossing_cusp_is_never_inside_out(topology):
    body = body_from_points(_crossing_cusp(), "cusp")
    size = (97, 25) if topology == "o" else (121, 25)
    r = mesh_body(body, circle(body, 15), topology, "elliptic", *size, wall_spacing=1e-4)
    assert _inside_out(r) == 0


def test_an_inside_out_grid_is_refused(monkeypatch):
    """Whatever the march does, a grid whose first rows lie inside the body is not
    written: the march's normals turned into the body must give a one-line refusal."""
    from pinn_engine.bodies import bodygrid, marching

    normals = bodygrid._row_normals
    monkeypatch.setattr(bodygrid, "_row_normals", lambda p, t: -normals(p, t))
    monkeypatch.setattr(marching, "library", lambda: None)  # NumPy's march, whose normals turn
    body = load_body(naca="0012")
    with pytest.raises(InputError, match="inside out"):
        mesh_body(body, circle(body, 15), "o", "tfi", 97, 25, wall_spacing=1e-4)


def _notched(depth: float, half: float) -> np.ndarray:
    """NACA 0012 opened to two prongs 2 * ``half`` apart at x = 1, a V notch between them
    reaching ``depth`` into the trailing edge (a fishtail edge)."""
    xy = naca4("0012", 101)
    xy[:, 1] += np.where(np.arange(len(xy)) <= len(xy) // 2, 1, -1) * half * xy[:, 0]
    apex = np.array([[1 - depth, 0.0]])
    return np.vstack([apex, xy, apex])


def test_an_inside_out_tfi_grid_is_refused_and_the_advice_works():
    """tfi's straight columns enter a notched trailing edge: refused in one line naming
    --method elliptic, whose grid (first rows along the wall's normals) is clean."""
    body = body_from_points(_notched(0.004, 0.003), "notched")
    far = circle(body, 15)
    with pytest.raises(InputError, match="inside out.*use --method elliptic") as info:
        mesh_body(body, far, "o", "tfi", 121, 33, wall_spacing=1e-4)
    assert "\n" not in str(info.value)
    r = mesh_body(body, far, "o", "elliptic", 121, 33, wall_spacing=1e-4)
    assert r.quality["folded_cells"] == 0 and r.quality["worst_max_angle"] < 180
    assert _inside_out(r) == 0


@real_files
@pytest.mark.parametrize("name, size", [("kenmar", (61, 17)), ("s1210", (121, 25))])
def test_real_inside_out_tfi_grids_are_refused_and_the_advice_works(name, size):
    """Real files whose coarse tfi O-grids are inside out: the advice's method is clean."""
    body = load_body(AIRFOILS / f"{name}.dat")
    far = circle(body, 15)
    with pytest.raises(InputError, match="inside out.*use --method elliptic"):
        mesh_body(body, far, "o", "tfi", *size)
    r = mesh_body(body, far, "o", "elliptic", *size)
    assert r.quality["folded_cells"] == 0 and r.quality["worst_max_angle"] < 180
    assert _inside_out(r) == 0


def test_a_first_layer_wider_than_a_notch_is_refused_and_the_advice_works():
    """The elliptic grid's first row leaves the wall along its normals at the first layer's
    height: wider than the notch (0.01 chord), it crosses into the opposite prong. The
    refusal names a first layer that keeps the row outside; with it the grid is written,
    not inside out."""
    body = body_from_points(_notched(0.02, 0.008), "notched")
    far = circle(body, 15)
    with pytest.raises(InputError, match=r"inside out.*at most (\S+) \(--spacing") as info:
        mesh_body(body, far, "o", "elliptic", 161, 41, wall_spacing=0.01)
    h = float(re.search(r"bottom=(\S+)\)", str(info.value))[1])
    r = mesh_body(body, far, "o", "elliptic", 161, 41, wall_spacing=h)
    assert _inside_out(r) == 0
    assert r.report["topology"]["first_layer"]["min"] == pytest.approx(h)


def test_lednicer_without_count_line_is_read(tmp_path):
    """Lednicer order with no name and no counts (as mdolab/prefoil's NACA 0012): upper then
    lower surface, each from the leading edge (it was read as a body enclosing no area)."""
    selig = naca4("0012", 41)
    le = int(np.argmin(selig[:, 0]))
    bare = tmp_path / "bare.dat"
    lednicer = np.vstack([selig[: le + 1][::-1], selig[le:]])
    bare.write_text("\n".join(f"{x:.7f} {y:.7f}" for x, y in lednicer) + "\n")
    xy, _ = read_dat(bare)
    np.testing.assert_allclose(xy, selig, atol=1e-7)
    assert xy[0, 1] >= 0 >= xy[-1, 1]  # Selig order: the upper surface first
    with_counts = tmp_path / "counts.dat"
    upper, lower = xy[: le + 1][::-1], xy[le:]
    rows = [f"{x:.7f} {y:.7f}" for x, y in upper] + [""] + [f"{x:.7f} {y:.7f}" for x, y in lower]
    with_counts.write_text(f"NACA 0012\n{len(upper)}. {len(lower)}.\n\n" + "\n".join(rows))
    np.testing.assert_allclose(read_dat(with_counts)[0], xy, atol=1e-7)


def test_lednicer_blocks_are_the_surfaces_whatever_the_counts(tmp_path):
    """A count line naming the two blocks the other way round (E850's file as published:
    "33 35" above blocks of 35 and 33 rows) cut the upper surface short and meshed a
    crossed wall: the blank-line blocks are the surfaces."""
    selig = naca4("2412", 41)
    le = int(np.argmin(selig[:, 0]))
    upper, lower = selig[: le + 1][::-1], selig[le:-3]  # the lower surface 3 rows shorter
    rows = [f"{x:.7f} {y:.7f}" for x, y in upper] + [""] + [f"{x:.7f} {y:.7f}" for x, y in lower]
    swapped = tmp_path / "swapped.dat"
    swapped.write_text(f"SWAPPED\n{len(lower)}. {len(upper)}.\n\n" + "\n".join(rows))
    xy, _ = read_dat(swapped)
    np.testing.assert_allclose(xy, selig[:-3], atol=1e-7)


def test_a_note_after_the_rows_starting_with_a_date_is_skipped(tmp_path):
    """AZ 2003's file ends with a note that starts with a date ("28/12/2005 modif ..."):
    a note, skipped; a row gone wrong there ("1.0000 (-0.0013)") is still refused."""
    rows = "".join(f"{x:.7f} {y:.7f}\n" for x, y in naca4("0012", 21))
    noted = tmp_path / "noted.dat"
    noted.write_text("AZ\n" + rows + "\npour Corde 365 mm\n28/12/2005 modif 08/05/2006\n")
    assert len(read_dat(noted)[0]) == 41
    broken = tmp_path / "broken.dat"
    broken.write_text("NACA\n" + rows + "1.0000     (-0.0013)\n")
    with pytest.raises(InputError, match="line 43 is not an 'x y' row"):
        read_dat(broken)


def _short_lower_surface() -> np.ndarray:
    """NACA 2412 whose lower surface ends 2 % chord short of the trailing edge, so that the
    segment closing the drawn points continues it along the chord (as STE 871-514's file)."""
    xy = naca4("2412", 61)
    lower = xy[61:]
    return np.vstack([xy[:61], lower[lower[:, 0] < 0.98]])


def test_a_closing_segment_that_continues_a_surface_is_no_base():
    """Such a segment has one corner, not a base's two (SPEC 9): the trailing edge is that
    corner, sharp, and the C-grid's cut leaves it (as the base's middle it folded the C-grid
    along the chord); the wall keeps every drawn point."""
    xy = _short_lower_surface()
    body = body_from_points(xy, "short")
    assert body.sharp and body.continued == "lower"
    np.testing.assert_allclose(body.surface[0], xy[0])
    np.testing.assert_allclose(body.surface[-1], xy[0])
    np.testing.assert_allclose(body.surface[:-1], xy)
    r = mesh_body(body, circle(body, 15), "c", "elliptic", 121, 25, wall_spacing=1e-4)
    assert r.report["topology"]["closing_segment_continues"] == "lower"
    assert r.quality["folded_cells"] == 0 and _inside_out(r) == 0
    te = r.points[0][r.report["topology"]["wake_nodes"]]
    np.testing.assert_allclose(te, xy[0], atol=1e-12)  # the cut leaves the corner


def test_a_base_keeps_its_two_corners():
    body = load_body(naca="4417", te="blunt")
    assert not body.sharp and body.continued is None


@real_files
def test_notes_after_the_coordinates_are_skipped():
    xy, name = read_dat(AIRFOILS / "ag24.dat")
    assert name.startswith("AG24") and len(xy) > 100


@real_files
def test_no_stray_numpy_warning():
    """lwk80100's C-grid printed 'invalid value encountered in sqrt' from bodygrid.py."""
    body = load_body(AIRFOILS / "lwk80100.dat")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for topology, size in (("o", (250, 80)), ("c", (300, 80))):
            mesh_body(body, circle(body, 15), topology, "elliptic", *size, wall_spacing=1e-5)


def _assert_clean(name: str, topology: str) -> None:
    """The issue's settings (O 250 x 80, C 300 x 80, first layer 1e-5, far field 15),
    elliptic: no folded cell, no cell of 180 degrees or more, not inside out."""
    body = load_body(AIRFOILS / f"{name}.dat")
    size = (250, 80) if topology == "o" else (300, 80)
    r = mesh_body(body, circle(body, 15), topology, "elliptic", *size, wall_spacing=1e-5)
    assert r.quality["folded_cells"] == 0
    assert r.quality["worst_max_angle"] < 180
    assert _inside_out(r) == 0


@real_files
@pytest.mark.parametrize("name", ["e387", "rae2822", "s1223", "goe464", "ag13"])
@pytest.mark.parametrize("topology", ["o", "c"])
def test_real_files_mesh_clean(name, topology):
    """Elliptic grids at a 1e-5 wall spacing on real files (high-lift, cusped, blunt): no
    folded cell, no cell of 180 degrees or more, not inside out."""
    _assert_clean(name, topology)


@real_files
@pytest.mark.parametrize(
    "name, topology",
    [
        ("e850", "o"),  # counts swapped: read as a crossed wall, refused inside out
        ("e850", "c"),
        ("ste87151", "c"),  # a closing segment along the chord: folded as a base
        ("trainer60", "c"),  # columns behind an aft thickest point crossing 1 to 2 chords out
        ("goe462", "o"),  # rows under a deep concave lower surface turned inside out
        ("ah93w480b", "c"),  # a 23 % base: its columns turned to run along it and folded
    ],
)
def test_files_that_failed_mesh_clean(name, topology):
    _assert_clean(name, topology)
