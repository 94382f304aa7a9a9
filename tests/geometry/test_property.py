"""Property-based tests (hypothesis) of boundary handling.

Random valid four-sided boundaries (star-shaped quadrilaterals with curved sides, and C-shaped
annular sectors that are not star-shaped), in random orientation, start vertex, scale and
offset, must give a grid whose corners are the constructed corners and whose boundary nodes
lie on the boundary. Random invalid boundaries, and arbitrary point clouds, must give
:class:`InputError` (a clear, one-line message), never another exception.

The suite runs a small profile. A longer one is run by hand::

    PINN_MESH_HYPOTHESIS=long .venv/bin/python -m pytest tests/geometry/test_property.py
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary, segment_distance, signed_area
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

settings.register_profile(
    "pinn-ci", max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "pinn-long", max_examples=3000, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
PROFILE = settings.get_profile(
    "pinn-long" if os.environ.get("PINN_MESH_HYPOTHESIS") == "long" else "pinn-ci"
)

unit = st.floats(0.0, 1.0)


# ---------------------------------------------------------------- valid boundaries


@st.composite
def quad_shape(draw):
    """A perturbed rectangle (corner angles 70..110 deg) with gently curved, resampled sides."""
    width = draw(st.floats(0.2, 5.0))
    rect = np.array([[0, 0], [width, 0], [width, 1], [0, 1]], dtype=float)
    jitter = np.array(draw(st.lists(st.floats(-0.08, 0.08), min_size=8, max_size=8)))
    corners = rect + jitter.reshape(4, 2) * min(width, 1.0)
    parts = []
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        n = draw(st.integers(1, 30))
        s = np.linspace(0.0, 1.0, n + 1)[:-1]
        if draw(st.booleans()):  # uneven spacing along the side
            s = np.sort(
                np.concatenate(
                    [
                        [0.0],
                        draw(
                            st.lists(
                                st.floats(0.02, 0.98), min_size=n - 1, max_size=n - 1, unique=True
                            )
                        ),
                    ]
                )
            )
        bump = draw(st.floats(-0.03, 0.03)) * np.sin(draw(st.integers(1, 2)) * np.pi * s)
        d = b - a
        parts.append(a + s[:, None] * d + bump[:, None] * np.array([-d[1], d[0]]))
    starts = np.cumsum([0] + [len(p) for p in parts[:-1]])
    return np.vstack(parts), list(starts)


@st.composite
def annulus_shape(draw):
    """An annular sector: a C shape, not star-shaped when it spans more than 180 degrees."""
    span = draw(st.floats(0.3, 1.7)) * np.pi
    r0 = 1.0
    r1 = r0 * draw(st.floats(1.15, 3.0))
    n_out, n_in = draw(st.integers(8, 60)), draw(st.integers(8, 60))
    t_out, t_in = np.linspace(0, span, n_out), np.linspace(span, 0, n_in)
    outer = np.column_stack([r1 * np.cos(t_out), r1 * np.sin(t_out)])
    m = draw(st.integers(0, 5))  # extra points on the radial ends
    radial = np.linspace(r1, r0, m + 2)[1:-1]
    end1 = np.column_stack([radial * np.cos(span), radial * np.sin(span)])
    inner = np.column_stack([r0 * np.cos(t_in), r0 * np.sin(t_in)])
    end2 = np.column_stack([radial[::-1] * 1.0, 0 * radial])
    ring = np.vstack([outer, end1, inner, end2])
    starts = [0, n_out - 1, n_out + m, n_out + m + n_in - 1]
    return ring, starts


@st.composite
def placed(draw, shape, duplicates: bool = True):
    """Random rotation, mirror, direction, start vertex, scale, offset and duplicates."""
    ring, corner_idx = draw(shape)
    corners = ring[corner_idx]
    angle = draw(st.floats(0, 2 * np.pi))
    rot = np.array([[np.cos(angle), np.sin(angle)], [-np.sin(angle), np.cos(angle)]])
    if draw(st.booleans()):
        rot = rot @ np.diag([1.0, -1.0])  # a mirror image: the ring turns clockwise
    scale = 10.0 ** draw(st.floats(-6, 8))
    offset = np.array(draw(st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4)))) * scale
    ring, corners = ring @ rot * scale + offset, corners @ rot * scale + offset
    if draw(st.booleans()):
        ring = ring[::-1]
    ring = np.roll(ring, draw(st.integers(0, len(ring) - 1)), axis=0)
    dups = draw(st.lists(st.integers(0, len(ring) - 1), max_size=3)) if duplicates else []
    for k in sorted(dups, reverse=True):
        ring = np.insert(ring, k, ring[k], axis=0)  # consecutive duplicates: repaired
    if duplicates and draw(st.booleans()):
        ring = np.vstack([ring, ring[:1]])  # the closing point repeated
    return ring, corners


valid_boundaries = st.one_of(placed(quad_shape()), placed(annulus_shape()))


@settings(PROFILE)
@given(valid_boundaries, st.integers(2, 30), st.integers(2, 30))
def test_valid_boundaries_give_a_grid_with_boundary_nodes_on_the_boundary(case, ni, nj):
    ring, corners = case
    b = Boundary.from_points(ring)
    size = float(np.ptp(ring, axis=0).max())
    tol = 1e-9 * size + 8 * float(np.spacing(np.abs(ring).max()))
    found = b.frame.to_user(b.corner_points())
    # the four constructed corners are found, and corner 0 has the smallest x + y
    dist = np.linalg.norm(found[:, None] - corners[None], axis=2)
    assert np.all(dist.min(axis=1) <= tol) and len(set(dist.argmin(axis=1))) == 4
    key = corners.sum(axis=1)
    if np.sort(key)[1] - key.min() > 1e-9 * size:  # no tie
        np.testing.assert_allclose(found[0], corners[np.argmin(key)], atol=tol)
    grid = Mesher(make_settings("tfi")).fit(b).predict(ni, nj).points
    assert grid.shape == (nj, ni, 2) and np.all(np.isfinite(grid))
    np.testing.assert_allclose(
        [grid[0, 0], grid[0, -1], grid[-1, -1], grid[-1, 0]], found, atol=tol
    )
    edge = np.concatenate([grid[0], grid[1:, -1], grid[-1, -2::-1], grid[-2:0:-1, 0]])
    on = segment_distance(edge, ring)
    assert on.max() <= tol, on.max()
    # bottom, right, top, left run once round the boundary, counter-clockwise
    ccw = ring if signed_area(ring) > 0 else ring[::-1]
    where = ring_position(edge, ccw)
    perimeter = float(np.linalg.norm(np.diff(np.vstack([ccw, ccw[:1]]), axis=0), axis=1).sum())
    steps = np.diff(np.append(where, where[0])) % perimeter
    assert abs(steps.sum() - perimeter) <= 1e-6 * perimeter


def ring_position(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Arc length along the closed ``ring`` of the nearest point to each of ``points``."""
    a, b = ring, np.roll(ring, -1, axis=0)
    ab = b - a
    length = np.linalg.norm(ab, axis=1)
    start = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    u = np.clip(
        np.einsum("pmj,mj->pm", points[:, None] - a, ab) / np.maximum(length**2, 1e-300), 0, 1
    )
    d = np.linalg.norm(a + u[..., None] * ab - points[:, None], axis=2)
    k = d.argmin(axis=1)
    return start[k] + u[np.arange(len(points)), k] * length[k]


# ---------------------------------------------------------------- invalid boundaries


@st.composite
def invalid_boundary(draw):
    """A boundary that is wrong in one of several ways; returns (points, reason)."""
    reason = draw(
        st.sampled_from(
            [
                "nonfinite",
                "too_few",
                "crossing",
                "polygon",
                "repeat",
                "spike",
                "collinear",
                "coincide",
            ]
        )
    )
    ring, _ = draw(placed(quad_shape(), duplicates=False))
    n = len(ring)
    k = draw(st.integers(0, n - 1))
    if reason == "nonfinite":
        ring = ring.copy()
        ring[k, draw(st.integers(0, 1))] = draw(st.sampled_from([np.nan, np.inf, -np.inf]))
    elif reason == "too_few":
        ring = ring[: draw(st.integers(0, 3))]
    elif reason == "crossing":  # one vertex pulled far through the opposite side
        centre = ring.mean(axis=0)
        ring = ring.copy()
        ring[k] = centre + 3.0 * (centre - ring[k])
    elif reason == "polygon":  # a regular polygon: 3 or 5+ corners, or a circle
        m = draw(st.sampled_from([3, 5, 6, 8, 40]))
        t = np.linspace(0, 2 * np.pi, m, endpoint=False) + draw(st.floats(0, 1))
        ring = np.column_stack([np.cos(t), np.sin(t)]) * 10.0 ** draw(st.floats(-3, 3))
    elif reason == "repeat":  # the ring visits a vertex twice
        j = (k + n // 2) % n
        ring = np.insert(ring, j, ring[k], axis=0)
    elif reason == "spike":  # out and back to the same point
        tip = ring[k] + (ring[(k + n // 3) % n] - ring[k]) * 0.5
        ring = np.insert(ring, k + 1, [tip, ring[k]], axis=0)
    elif reason == "collinear":
        t = np.sort(np.array(draw(st.lists(unit, min_size=4, max_size=20))))
        ring = np.column_stack([t, 2 * t + 1])
    elif reason == "coincide":
        ring = np.repeat(ring[:1], draw(st.integers(1, 10)), axis=0)
    return ring, reason


@settings(PROFILE)
@given(invalid_boundary())
def test_invalid_boundaries_give_a_clear_error(case):
    ring, reason = case
    with pytest.raises(InputError) as err:
        Boundary.from_points(ring)
    message = str(err.value)
    assert "\n" not in message and len(message) < 400


finite_or_not = st.floats(allow_nan=True, allow_infinity=True, width=64)
coordinate = st.one_of(
    st.floats(-1e3, 1e3), finite_or_not, st.sampled_from([0.0, 1.0, 1e-300, 1e300])
)


@settings(PROFILE)
@given(st.lists(st.tuples(coordinate, coordinate), max_size=40))
def test_arbitrary_points_give_a_grid_or_a_clear_error(points):
    pts = np.array(points, dtype=float).reshape(-1, 2)
    try:
        b = Boundary.from_points(pts)
    except InputError as exc:
        assert "\n" not in str(exc)
        return
    grid = Mesher(make_settings("tfi")).fit(b).predict(5, 4)
    assert np.all(np.isfinite(grid.points))
    assert b.deviation(b.frame.to_unit(grid.points[0])).max() <= 1e-9


@settings(PROFILE, max_examples=max(PROFILE.max_examples // 3, 10))
@given(
    st.one_of(valid_boundaries, invalid_boundary()),
    st.sampled_from([".csv", ".txt"]),
    st.booleans(),
)
def test_cli_answers_status_0_with_a_grid_or_2_with_one_line(case, ext, header):
    ring = case[0]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"boundary{ext}"
        rows = [
            " ".join(repr(float(v)) for v in row)
            if ext == ".txt"
            else ",".join(repr(float(v)) for v in row)
            for row in ring
        ]
        path.write_text("\n".join((["x,y"] if header else []) + rows) + "\n")
        out = Path(folder) / "g.vts"
        import contextlib
        import io

        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            rc = main([str(path), "--method", "tfi", "--size", "9", "5", "-o", str(out), "--quiet"])
        if isinstance(case[1], str):  # an invalid case
            assert rc == 2
        assert rc in (0, 2)
        if rc == 0:
            assert out.is_file()
        else:
            lines = err.getvalue().strip().splitlines()
            assert len(lines) == 1 and lines[0].startswith("pinn-mesh: error: ")
            assert not out.exists()
        assert not list(Path(folder).glob("*.part"))
