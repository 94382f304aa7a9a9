"""Boundary validation, corner detection and the side convention (SPEC 1)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import square_ring, wavy_ring

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary


def corner_set(points: np.ndarray, corners=None) -> set[tuple[float, float]]:
    b = Boundary.from_points(points, corners)
    user = b.frame.to_user(b.corner_points())
    return {tuple(np.round(p, 9)) for p in user}


def rotate(p: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return p @ np.array([[c, s], [-s, c]])


@pytest.mark.parametrize("angle", [0.3, 1.2, 2.5, -2.0])
def test_corners_unchanged_under_rotation(angle):
    ring = wavy_ring()
    expected = {tuple(np.round(rotate(p[None], angle)[0], 9)) for p in ring[[0, 24, 48, 72]]}
    assert corner_set(rotate(ring, angle)) == expected


def test_corners_unchanged_under_reversal_scaling_and_shift():
    ring = wavy_ring()
    base = corner_set(ring)
    assert corner_set(ring[::-1]) == base
    assert corner_set(np.roll(ring, 7, axis=0)) == base
    assert corner_set(np.roll(ring[::-1], -13, axis=0)) == base
    scaled = {tuple(np.round(1000 * np.array(p) + [5e4, -3e3], 6)) for p in base}
    got = corner_set(ring * 1000 + [5e4, -3e3])
    assert {tuple(np.round(p, 6)) for p in got} == scaled


def test_side_convention_corner0_smallest_x_plus_y_and_ccw():
    ring = np.roll(wavy_ring()[::-1], 30, axis=0)  # clockwise, shifted start
    b = Boundary.from_points(ring)
    c = b.frame.to_user(b.corner_points())
    np.testing.assert_allclose(c, [[0, 0], [2, 0], [2, 1], [0, 1]], atol=1e-12)
    bottom = b.frame.to_user(b.side("bottom").points)
    assert bottom[0, 0] < bottom[-1, 0]
    left = b.frame.to_user(b.side("left").points)
    assert left[0, 1] < left[-1, 1]  # left runs along increasing eta


def test_tie_on_x_plus_y_takes_smallest_y():
    diamond = np.array([[0, 1], [1, 0], [2, 1], [1, 2]], dtype=float)
    # corners (0,1) and (1,0) have x+y = 1; corner 0 is the one with smaller y
    b = Boundary.from_points(diamond)
    np.testing.assert_allclose(b.frame.to_user(b.corner_points()[0]), [1, 0])


def test_named_corners_override_detection():
    ring = square_ring(4)
    # pretend the corners are the side midpoints; detection would pick the real corners
    mids = (2, 6, 10, 14)
    b = Boundary.from_points(ring, mids)
    assert {tuple(p) for p in b.frame.to_user(b.corner_points())} == {tuple(ring[i]) for i in mids}


def test_closing_point_and_consecutive_duplicates_are_dropped():
    ring = square_ring(4)
    doubled = np.repeat(ring, 2, axis=0)
    closed = np.vstack([doubled, doubled[:1]])
    b = Boundary.from_points(closed)
    assert len(b.ring) == len(ring)


def test_pentagon_and_circle_have_no_four_clear_corners():
    angles = np.linspace(0, 2 * np.pi, 6)[:-1]
    pentagon = np.column_stack([np.cos(angles), np.sin(angles)])
    with pytest.raises(InputError, match="fewer than four clear corners"):
        Boundary.from_points(pentagon)
    circle = np.column_stack([np.cos(np.linspace(0, 6.2, 60)), np.sin(np.linspace(0, 6.2, 60))])
    with pytest.raises(InputError, match="fewer than four clear corners"):
        Boundary.from_points(circle)


def test_self_intersecting_boundary_is_an_error():
    bowtie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], dtype=float)
    with pytest.raises(InputError, match="self-intersecting"):
        Boundary.from_points(bowtie)
    ring = square_ring(8)
    ring[3] = [0.3, 0.6]  # pull a bottom vertex across the interior
    ring[4] = [0.5, 1.5]
    with pytest.raises(InputError, match="self-intersecting"):
        Boundary.from_points(ring)


def test_repeated_point_is_an_error():
    ring = square_ring(8)
    ring = np.insert(ring, 20, ring[5], axis=0)  # the ring visits point 5 twice
    with pytest.raises(InputError, match="repeated|self-intersecting"):
        Boundary.from_points(ring)


def test_consecutive_points_a_micro_segment_apart_are_not_a_touch():
    """Two consecutive side points 1.3e-6 apart (above the merge tolerance, in one square of
    the touch check) lie along the ring: the boundary is valid, a grid meshes it."""
    ring = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0.53226745], [0, 0.53226614]])
    b = Boundary.from_points(ring)
    assert len(b.ring) == 6 and b.corners == (0, 1, 2, 3)
    again = np.insert(ring, 5, [0.4, 0.53226700], axis=0)  # a real touch nearby still is one
    with pytest.raises(InputError, match="repeated|self-intersecting|doubles back"):
        Boundary.from_points(again)


def test_non_finite_point_is_an_error():
    ring = square_ring(4)
    ring[3, 1] = np.nan
    with pytest.raises(InputError, match="not finite"):
        Boundary.from_points(ring)
    ring[3, 1] = np.inf
    with pytest.raises(InputError, match="not finite"):
        Boundary.from_points(ring)


def test_bad_named_corners():
    with pytest.raises(InputError, match="four different"):
        Boundary.from_points(square_ring(4), (0, 0, 4, 8))
    with pytest.raises(InputError, match="out of range"):
        Boundary.from_points(square_ring(4), (0, 4, 8, 99))


def test_a_self_intersecting_boundary_says_where_and_what_to_change():
    """The crossing's point in the user's units, and the fix."""
    bowtie = np.array([[0.0, 0.0], [4.0, 2.0], [4.0, 0.0], [0.0, 2.0]]) + [10.0, 5.0]
    with pytest.raises(InputError, match=r"cross at \(12, 6\); move those points") as info:
        Boundary.from_points(bowtie)
    assert "\n" not in str(info.value)
