"""Auxiliary-line computational coordinates (SPEC 2)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import square_ring

from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import RawLine, crossing_turns, map_line
from pinn_engine.geometry.boundary import Boundary


@pytest.fixture
def square() -> Boundary:
    return Boundary.from_points(square_ring(10, size=2.0))


def line(points, xi_eta=None, name="aux line 0") -> RawLine:
    return RawLine(np.asarray(points, dtype=float), xi_eta, name)


def test_bottom_to_top_line_hand_checked(square):
    # from (0.6, 0) on the bottom (s_b = 0.3) to (1.4, 2) on the top (s_t = 0.7)
    aux = map_line(line([[0.6, 0.0], [1.0, 1.0], [1.4, 2.0]]), square)
    t = np.linspace(0, 1, len(aux.xi_eta))
    np.testing.assert_allclose(aux.xi_eta[:, 0], 0.3 + 0.4 * t, atol=1e-12)
    np.testing.assert_allclose(aux.xi_eta[:, 1], t, atol=1e-12)
    # the midpoint of the line, (1, 1) in user units, is (0.5, 0.5) in the working frame
    mid = len(t) // 2
    np.testing.assert_allclose(square.frame.to_user(aux.xy[mid]), [1.0, 1.0], atol=1e-12)
    assert aux.sides == ("bottom", "top")


def test_crossing_turns_measure_the_kink_at_the_line(square):
    """A straight lattice's rows cross a line at xi = 0.5 without turning; rows bent by 10
    degrees at that column turn 10 there; a left-right line is crossed by the columns."""
    xi, eta = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 5))
    grid = np.stack([xi, eta], axis=-1)
    vertical = map_line(line([[1.0, 0.0], [1.0, 2.0]], name="v"), square)
    across = map_line(line([[0.0, 1.0], [2.0, 1.0]], name="h"), square)
    assert crossing_turns(grid, [vertical, across]) == pytest.approx(
        {vertical.name: 0.0, across.name: 0.0}, abs=1e-6
    )
    bent = grid.copy()
    rise = np.tan(np.radians(10.0)) * np.clip(xi - 0.5, 0.0, None)
    bent[..., 1] += rise * (eta > 0) * (eta < 1)  # the interior rows only
    assert crossing_turns(bent, [vertical])[vertical.name] == pytest.approx(10.0, abs=1e-6)


def test_line_drawn_the_other_way_and_left_right(square):
    forward = map_line(line([[0.6, 0.0], [1.4, 2.0]]), square)
    backward = map_line(line([[1.4, 2.0], [0.6, 0.0]]), square)
    np.testing.assert_allclose(forward.xi_eta, backward.xi_eta, atol=1e-12)
    # right (s_r = 0.25 at y = 0.5) to left (s_l = 0.75 at y = 1.5): eta = s_l + t (s_r - s_l)
    across = map_line(line([[2.0, 0.5], [0.0, 1.5]]), square)
    t = np.linspace(0, 1, len(across.xi_eta))
    np.testing.assert_allclose(across.xi_eta[:, 0], t, atol=1e-12)
    np.testing.assert_allclose(across.xi_eta[:, 1], 0.75 - 0.5 * t, atol=1e-12)


def test_xi_eta_point_data_override(square):
    xe = np.array([[0.1, 0.2], [0.3, 0.4]])
    aux = map_line(line([[0.5, 0.5], [1.0, 1.0]], xi_eta=xe), square)
    np.testing.assert_array_equal(aux.xi_eta, xe)


@pytest.mark.parametrize(
    "points, message",
    [
        ([[0.6, 0.0], [2.0, 0.8]], "opposite sides"),  # bottom to right
        ([[0.6, 0.5], [1.4, 2.0]], "opposite sides"),  # starts inside
        ([[0.6, 0.0], [1.0, 2.5], [1.4, 2.0]], "crosses the boundary"),
    ],
)
def test_bad_lines_name_the_line(square, points, message):
    with pytest.raises(InputError, match=message) as err:
        map_line(line(points, name="lines.vtp line 3"), square)
    assert "lines.vtp line 3" in str(err.value)
