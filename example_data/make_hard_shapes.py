"""Regenerate the hard four-sided shapes of ``example_data/hard/`` (the quality benchmark's set).

Run ``.venv/bin/python example_data/make_hard_shapes.py``. Each shape is chosen for what breaks
structured meshers: deep and narrow notches (a map with large, local derivatives), steps,
corners of 35 degrees or less, a 270-degree sector, long channels, a 4:1 nozzle, an S-duct, a
bump. Features are rounded finely enough that each side stays one smooth curve (the four
corners are the only sharp turns) and every side is resampled evenly by arc length.
``hard/<name>.vtp`` holds the boundary, ``hard/<name>_aux.vtp`` its auxiliary lines if any.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from make_examples import HERE, polydata, ring, write

OUT = HERE / "hard"
Curve = Callable[[np.ndarray], np.ndarray]


def resample(points: np.ndarray, n: int) -> np.ndarray:
    """``n`` points evenly spaced by arc length along a densely sampled curve."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)]) / seg.sum()
    t = np.linspace(0.0, 1.0, n)
    return np.column_stack([np.interp(t, s, points[:, 0]), np.interp(t, s, points[:, 1])])


def line(a, b, n: int = 41) -> np.ndarray:
    return np.linspace(np.asarray(a, float), np.asarray(b, float), n)


def graph(
    f: Callable[[np.ndarray], np.ndarray], x0: float, x1: float, n: int = 241, dense: int = 40001
) -> np.ndarray:
    """The curve y = f(x) from x0 to x1, resampled by arc length."""
    x = np.linspace(x0, x1, dense)
    return resample(np.column_stack([x, f(x)]), n)


def step(u: np.ndarray) -> np.ndarray:
    """Smooth step from 0 to 1 around u = 0 (width about 1)."""
    return 0.5 * (1 + np.tanh(2 * u))


def slot(x: np.ndarray, centre: float, width: float, depth: float, edge: float) -> np.ndarray:
    """Depth profile of a flat-bottomed slot with rounded edges of size ``edge``."""
    return depth * step((x - centre + width / 2) / edge) * step((centre + width / 2 - x) / edge)


def box_with_top(width: float, height: float, top: Callable, n_top: int = 321) -> np.ndarray:
    """A box whose top is y = top(x); corners (0,0), (w,0), (w,top(w)), (0,top(0))."""
    return ring(
        line((0, 0), (width, 0), 81),
        line((width, 0), (width, top(np.array(width))), 41),
        graph(top, width, 0.0, n_top),
        line((0, top(np.array(0.0))), (0, 0), 41),
    )


def notch_narrow_deep():
    """The issue's case: a unit square with a narrow slot 80 % deep, aux line down its middle."""
    top = lambda x: 1 - slot(x, 0.5, 0.1, 0.8, 0.02)  # noqa: E731
    return box_with_top(1.0, 1.0, top, 401), [line((0.5, 0.0), (0.5, 0.2), 21)]


def notch_gauss():
    """A Gaussian notch 60 % deep in the top of a 2:1 box, aux line down its middle."""
    top = lambda x: 1 - 0.6 * np.exp(-(((x - 1) / 0.12) ** 2))  # noqa: E731
    return box_with_top(2.0, 1.0, top), [line((1.0, 0.0), (1.0, 0.4), 21)]


def notch_v_sharp():
    """A V notch 70 % deep with a tip rounded to 0.5 % of the width."""
    top = lambda x: 1 - 0.7 * np.maximum(0, 1 - np.sqrt((x - 0.5) ** 2 + 0.005**2) / 0.2)  # noqa: E731
    return box_with_top(1.0, 1.0, top), []


def notch_wide_shallow_offset():
    """A wide slot 40 % deep, off-centre near the right corner."""
    top = lambda x: 1 - slot(x, 0.75, 0.3, 0.4, 0.01)  # noqa: E731
    return box_with_top(1.0, 1.0, top), []


def two_slots():
    """Staggered slots 50 % deep from the bottom and the top of a 2:1 channel (a baffle maze)."""
    bottom = graph(lambda x: slot(x, 0.7, 0.08, 0.5, 0.015), 0.0, 2.0, 321)
    top = graph(lambda x: 1 - slot(x, 1.3, 0.08, 0.5, 0.015), 2.0, 0.0, 321)
    return ring(bottom, line((2, 0), (2, 1)), top, line((0, 1), (0, 0))), []


def backward_step():
    """A channel with a smoothed backward-facing step of half the outlet height."""
    bottom = graph(lambda x: 0.5 * (1 - step((x - 1.0) / 0.03)), 0.0, 4.0, 321)
    return ring(
        bottom, line((4, 0), (4, 1)), line((4, 1), (0, 1), 161), line((0, 1), (0, 0.5), 21)
    ), []


def dart_30():
    """A dart with a 30-degree corner at its tip and three corners of 106 to 112 degrees."""
    a, b, c, d = (0, 0), (2.5, -0.67), (3.0, 0.0), (2.5, 0.67)
    return ring(line(a, b, 121), line(b, c, 21), line(c, d, 21), line(d, a, 121)), []


def kite_35():
    """Two opposite 35-degree corners: a strongly skewed parallelogram with a curved top."""
    a = np.radians(35)
    d = 1.0 / np.tan(a)
    bottom = line((0, 0), (2, 0), 81)
    right = line((2, 0), (2 + d, 1), 41)
    top = graph(lambda x: 1 + 0.15 * np.sin(np.pi * (x - d) / 2), 2 + d, d, 161)
    return ring(bottom, right, top, line((d, 1), (0, 0), 41)), []


def sector_270():
    """A 270-degree sector of an annulus (radii 0.5 and 1): bottom the inner arc."""
    t = np.linspace(0, 1.5 * np.pi, 241)
    inner = 0.5 * np.column_stack([np.cos(t), np.sin(t)])
    outer = np.column_stack([np.cos(t), np.sin(t)])[::-1]
    return ring(inner, line(inner[-1], outer[0], 21), outer, line(outer[-1], inner[0], 21)), []


def channel_12():
    """A 12:1 channel with wavy walls of opposite phase."""
    bottom = graph(lambda x: 0.2 * np.sin(np.pi * x / 2), 0.0, 12.0, 481)
    top = graph(lambda x: 1 - 0.2 * np.sin(np.pi * x / 2 + 1), 12.0, 0.0, 481)
    return ring(bottom, line((12, 0), top[0]), top, line(top[-1], (0, 0))), []


def nozzle_4():
    """A converging-diverging nozzle, inlet height 4 times the throat's; a slanted aux line
    across the throat."""
    h = lambda x: 0.125 + 0.375 * (1 - np.exp(-(((x - 1.0) / 0.35) ** 2)))  # noqa: E731
    bottom = graph(lambda x: -h(x), 0.0, 3.0, 241)
    top = graph(h, 3.0, 0.0, 241)
    return ring(bottom, line(bottom[-1], top[0]), top, line(top[-1], bottom[0])), [
        line((0.9, -h(0.9)), (1.1, h(1.1)), 21)
    ]


def s_duct():
    """An S-duct: the centreline shifts by 1.5 widths over 3 widths of length."""
    c = lambda x: 1.5 * step((x - 1.5) / 0.6)  # noqa: E731
    bottom = graph(c, 0.0, 3.0, 241)
    top = graph(lambda x: c(x) + 1, 3.0, 0.0, 241)
    return ring(bottom, line(bottom[-1], top[0]), top, line(top[-1], bottom[0])), []


def bump():
    """A bump channel (bump 40 % of the height); an aux line straight across the channel
    just above the crest (a flat grid row over the bump)."""
    bottom = graph(lambda x: 0.4 * np.exp(-(((x - 1.5) / 0.25) ** 2)), 0.0, 3.0, 241)
    return ring(bottom, line((3, 0), (3, 1)), line((3, 1), (0, 1), 121), line((0, 1), (0, 0))), [
        line((0.0, 0.55), (3.0, 0.55), 81)
    ]


SHAPES = {
    f.__name__: f
    for f in (
        notch_narrow_deep,
        notch_gauss,
        notch_v_sharp,
        notch_wide_shallow_offset,
        two_slots,
        backward_step,
        dart_30,
        kite_35,
        sector_270,
        channel_12,
        nozzle_4,
        s_duct,
        bump,
    )
}


def main() -> None:
    OUT.mkdir(exist_ok=True)
    for name, make in SHAPES.items():
        boundary, aux = make()
        write(polydata([boundary], closed=True), f"hard/{name}.vtp")
        if aux:
            write(polydata(aux, closed=False), f"hard/{name}_aux.vtp")


if __name__ == "__main__":
    main()
