"""Airfoils and bodies as inputs (SPEC 9): readers, NACA sections, trailing edges, far fields."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import write_selig

from pinn_engine.bodies.airfoil import body_from_points, circle, load_body, naca4, read_dat
from pinn_engine.classical.spacing import exact_stretch
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import segment_distance


def test_selig_and_lednicer_give_the_same_airfoil(tmp_path):
    xy = naca4("2412", points=41)
    a, name = read_dat(write_selig(tmp_path / "a.dat", xy, "NACA 2412"))
    n = 41
    upper, lower = xy[:n][::-1], xy[n - 1 :]
    text = (
        "NACA 2412\n41. 41.\n\n"
        + "\n".join(f"{x} {y}" for x, y in upper)
        + "\n\n"
        + "\n".join(f"{x} {y}" for x, y in lower)
        + "\n"
    )
    (tmp_path / "b.dat").write_text(text)
    b, _ = read_dat(tmp_path / "b.dat")
    assert name == "NACA 2412"
    np.testing.assert_allclose(a, xy, atol=1e-6)
    np.testing.assert_allclose(b, xy, atol=1e-6)


@pytest.mark.parametrize(
    "text, words",
    [
        ("name\n1 0\n0.5 x\n", "not an 'x y' row"),
        ("name\n1 0\n0 0\n", "at least 3"),
        ("just a name\n", "no 'x y' coordinate rows"),
    ],
)
def test_bad_dat_files_fail_in_one_line(tmp_path, text, words):
    path = tmp_path / "bad.dat"
    path.write_text(text)
    with pytest.raises(InputError, match=words) as info:
        read_dat(path)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("code", ["12", "00a2", "0000", "2012"])
def test_bad_naca_codes(code):
    with pytest.raises(InputError, match="NACA"):
        naca4(code)


def test_naca_sections():
    sharp, blunt = naca4("0012"), naca4("0012", te="blunt")
    np.testing.assert_allclose(sharp[0], sharp[-1])
    assert blunt[0, 1] - blunt[-1, 1] == pytest.approx(0.00252, abs=2e-5)
    assert np.ptp(sharp[:, 1]) == pytest.approx(0.12, abs=2e-3)
    body = load_body(naca="4412")
    assert body.sharp and body.chord == pytest.approx(1.0, abs=1e-3)
    np.testing.assert_allclose(body.mid_chord, (0.5, 0.0), atol=3e-3)


def test_farfield_must_enclose_the_body():
    body = load_body(naca="0012")
    with pytest.raises(InputError, match="at least 1 chord"):
        circle(body, 0.4)


def test_exact_stretching():
    """The body grids' distributions: spacing.py's Vinokur stretching, end intervals exact."""
    s = exact_stretch(41, 1e-4)[0]
    assert s[1] == pytest.approx(1e-4, rel=1e-8) and np.all(np.diff(s) > 0)
    t = exact_stretch(61, 2e-3, 1e-2)[0]
    assert t[1] == pytest.approx(2e-3, rel=1e-8) and 1 - t[-2] == pytest.approx(1e-2, rel=1e-8)
    columns = exact_stretch(30, np.array([1e-5, 1e-3]), None, lines=2)
    np.testing.assert_allclose(columns[:, 1], [1e-5, 1e-3], rtol=1e-8)
    assert (np.diff(columns, axis=1) > 0).all()


def test_inside_polygon_needs_no_matplotlib():
    """The far-field polyline's inside test (even-odd rule): points of a concave star."""
    from pinn_engine.bodies.airfoil import inside_polygon

    th = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    r = np.where(np.arange(10) % 2 == 0, 2.0, 1.0)
    star = np.column_stack([r * np.cos(th), r * np.sin(th)])
    pts = np.array([[0.0, 0.0], [1.9, 0.0], [3.0, 0.0], [1.5 * np.cos(th[1]), 1.5 * np.sin(th[1])]])
    assert inside_polygon(pts, star).tolist() == [True, True, False, False]


def _flatback_ring(start_mid_base: bool) -> np.ndarray:
    """NACA 0030 opened to a flatback base of 0.2 chord, closed by its base drawn as part
    of the ring: from the base's middle (1, 0) as NuMAD files start, or from its corner."""
    xy = naca4("0030", 101)
    n = len(xy) // 2
    xy[:, 1] += np.where(np.arange(len(xy)) <= n, 0.5, -0.5) * 0.2 * xy[:, 0]
    if start_mid_base:
        return np.vstack([[[1.0, 0.0], [1.0, 0.05]], xy, [[1.0, -0.05], [1.0, 0.0]]])
    return np.vstack([xy, [[1.0, 0.0]], xy[:1]])


@pytest.mark.parametrize("start_mid_base", [True, False])
def test_the_trailing_edge_is_found_from_the_shape_not_the_file_start(start_mid_base):
    body = body_from_points(_flatback_ring(start_mid_base), "numad")
    assert not body.sharp and not body.rounded
    assert np.allclose(body.surface[0], (1.0, 0.1)) and np.allclose(body.surface[-1], (1.0, -0.1))
    assert body.te_gap == pytest.approx(0.2)


def test_a_sharp_trailing_edge_is_its_corner_where_the_file_starts_elsewhere():
    xy = naca4("2412", 81)
    ring = np.vstack([xy[30:-1], xy[:31]])  # starts on the upper surface, closed
    body = body_from_points(ring, "shifted")
    assert body.sharp and np.allclose(body.surface[0], (1.0, 0.0))


def _openfast_file(path, xy, reference=(0.25, 0.0)):
    """An OpenFAST (AeroDyn) airfoil file: NumCoords, '!' comments, the reference point."""
    rows = "".join(f" {x:.12e} {y:.12e}\n" for x, y in xy)
    path.write_text(
        f"  {len(xy) + 1}   NumCoords   ! The number of coordinates (incl. the reference)\n"
        "! x-y coordinate of airfoil reference\n!  x/c        y/c\n"
        f" {reference[0]:.6f}       {reference[1]:g}\n"
        "! coordinates of airfoil shape\n! interpolation to 200 points\n!  x/c        y/c\n" + rows
    )
    return path


def test_an_openfast_coords_file_is_read_without_its_reference_point(tmp_path):
    xy = naca4("2412", 81)[::-1]  # clockwise, as many OpenFAST files run
    got, name = read_dat(_openfast_file(tmp_path / "AF05_Coords.txt", xy))
    assert name == "AF05_Coords" and np.allclose(got, xy)
    body = load_body(tmp_path / "AF05_Coords.txt")
    assert body.sharp and np.allclose(body.surface[0], (1.0, 0.0))


def test_the_wall_stays_within_the_tolerance_of_sparse_points_round_a_bend():
    """A section drawn with few points, evenly in x, round a blunt nose: the spline through
    them swings 1.1 % chord off the polyline there; the wall is held within 0.05 %."""
    from pinn_engine.bodies.bodygrid import WALL_HOLD, BodyCurve

    x = np.linspace(0.0, 1.0, 41)
    upper = np.c_[x, 0.3 * np.sqrt(x) * (1 - x) + 0.02 * (1 - x)]
    xy = np.vstack([upper[::-1], (upper * (1, -1))[1:]])
    xy[0] = xy[-1] = (1.0, 0.0)
    body = body_from_points(xy, "wedge")
    curve = BodyCurve(body)
    wall = curve.at(np.linspace(0, curve.length, 4001))
    off = segment_distance(wall, body.ring()[:-1]) / body.chord
    assert off.max() <= WALL_HOLD * (1 + 1e-9)
