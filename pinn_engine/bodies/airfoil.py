"""Bodies and far fields of O- and C-grids (SPEC 9): airfoil files, NACA sections, circles.

- Selig ``.dat``: a name line, then ``x y`` rows from the trailing edge over the upper
  surface to the leading edge and back along the lower surface (counter-clockwise).
- OpenFAST (AeroDyn) airfoil files (``*_Coords.txt``): ``N NumCoords``, ``!`` comments,
  the reference point (skipped), then the coordinates in either sense.
- Lednicer ``.dat``: a name line, a row ``NU NL`` (point counts), then the upper surface
  from leading to trailing edge and the lower surface likewise (blank lines between); the
  count line may be missing (the points then start at the leading edge).
- ``naca4("2412")``: the NACA 4-digit section of chord 1. ``te="sharp"`` (default) closes the
  trailing edge (thickness coefficient -0.1036, so the C-grid applies); ``te="blunt"`` is the
  classical formula (-0.1015), whose trailing edge of thickness 0.21 % t/c (0.25 % chord for
  12 %) is closed by a straight base, the usual O-grid body.
- A far field is a circle (radius R chords about the body's mid-chord) or a closed polyline.

A :class:`Body` holds the closed body curve counter-clockwise, starting at the trailing edge
(the point of largest x; the middle of a blunt trailing edge's base).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError

_NUMBER = re.compile(
    r"^[\s]*[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?[\s,;]+"
    r"[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?[\s,;]*$"
)
# A line whose first word is a number (a coordinate row gone wrong, not a note such as a date)
_LEADING_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?(\s|$)")
# An OpenFAST airfoil file (AeroDyn's): a "N NumCoords" line, '!' comments, then the
# airfoil's reference point (its aerodynamic centre) before the coordinates
_OPENFAST = re.compile(r"^\s*\d+\s+NumCoords\b", re.MULTILINE)
# Lednicer's order without its count line: the points start within this share of the chord
# from the leading edge (Selig's start at the trailing edge), and x falls back by at least
# this share of the chord where the second surface starts at the leading edge again
LEDNICER_START, LEDNICER_RESTART = 0.25, 0.5


def xy_blocks(text: str, source: str) -> tuple[list[list[tuple[float, float]]], str]:
    """Blocks of numeric ``x y`` rows separated by blank lines, and the name line (the first
    line). Text lines before the first row (a header of several lines) and after the last
    (a note or a source) are skipped; a line that begins with a number but is no ``x y``
    row, or text between the rows, is refused."""
    blocks: list[list[tuple[float, float]]] = [[]]
    name = ""
    lines = text.splitlines()
    rows = [k for k, line in enumerate(lines) if _NUMBER.match(line)]
    for k, line in enumerate(lines):
        if _NUMBER.match(line):
            a, b = re.split(r"[\s,;]+", line.strip().replace("d", "e").replace("D", "e"))[:2]
            blocks[-1].append((float(a), float(b)))
            continue
        if k == 0:
            name = line.strip()
        stripped = line.strip()
        after = bool(rows) and k > rows[0]
        if stripped and after and (k < rows[-1] or _LEADING_NUMBER.match(stripped)):
            raise InputError(f"line {k + 1} is not an 'x y' row: {stripped[:40]!r}", source)
        if blocks[-1]:
            blocks.append([])
    return [b for b in blocks if b], name


def _lednicer_surfaces(xy: np.ndarray) -> np.ndarray | None:
    """Selig order of points that run as two surfaces, each from the leading edge to the
    trailing edge (Lednicer's order without its count line), or None for points that run
    once around the body: such a file starts at the leading edge (the smallest x), not at
    the trailing edge, and x falls back to the leading edge once, by at least half the
    chord, where the second surface begins."""
    x = xy[:, 0]
    span = float(np.ptp(x))
    if span <= 0 or x[0] - x.min() > LEDNICER_START * span:
        return None
    drops = x[:-1] - x[1:]
    k = int(np.argmax(drops)) + 1
    if drops[k - 1] < LEDNICER_RESTART * span:
        return None
    upper, lower = xy[:k], xy[k:]
    return np.concatenate([upper[::-1], lower[1:] if np.allclose(lower[0], upper[0]) else lower])


def read_dat(path: str | os.PathLike) -> tuple[np.ndarray, str]:
    """Airfoil coordinates of a Selig or Lednicer ``.dat`` file (Lednicer with or without
    its count line), in Selig order (upper trailing edge -> leading edge -> lower trailing
    edge), and the airfoil's name."""
    source = str(path)
    try:
        text = Path(path).read_text(errors="replace")
    except OSError as exc:
        raise InputError(f"cannot read the file ({exc.strerror or exc})", source) from None
    openfast = _OPENFAST.search(text) is not None
    if openfast:  # '!' starts a comment; the first row is the airfoil's reference point
        text = "\n".join("" if s.lstrip().startswith("!") else s for s in text.splitlines())
    blocks, name = xy_blocks(text, source)
    if openfast and blocks and len(blocks[0]) == 1:
        blocks = blocks[1:]
        name = Path(path).stem
    if not blocks:
        raise InputError(
            "holds no 'x y' coordinate rows (expected a Selig or Lednicer airfoil file)", source
        )
    first = blocks[0][0]
    lednicer = (
        first[0] >= 2
        and first[1] >= 2
        and float(first[0]).is_integer()
        and float(first[1]).is_integer()
    )
    if lednicer:
        nu, nl = int(first[0]), int(first[1])
        surfaces = [b for b in [blocks[0][1:], *blocks[1:]] if b]
        pts = [p for b in surfaces for p in b]
        if len(pts) != nu + nl:
            raise InputError(
                f"Lednicer header announces {nu} + {nl} points but the file holds {len(pts)}",
                source,
            )
        # two blocks are the two surfaces, whatever counts they announce (some files swap them)
        upper, lower = (
            (np.array(surfaces[0]), np.array(surfaces[1]))
            if len(surfaces) == 2
            else (np.array(pts[:nu]), np.array(pts[nu:]))
        )
        xy = np.concatenate([upper[::-1], lower[1:] if np.allclose(lower[0], upper[0]) else lower])
    else:
        xy = np.array([p for b in blocks for p in b])
        surfaces = _lednicer_surfaces(xy) if len(xy) >= 5 else None
        xy = xy if surfaces is None else surfaces
    if len(xy) < MIN_POINTS:
        raise InputError(
            f"has {len(xy)} coordinate rows; a body needs at least {MIN_POINTS}", source
        )
    if not np.isfinite(xy).all():
        raise InputError("has non-finite coordinates", source)
    return xy, name or Path(path).stem


# A body is at least a triangle: three points (a closed wedge)
MIN_POINTS = 3
# SPEC 9: a trailing-edge gap of at most this many chords counts as sharp (many public .dat
# files leave one of about 1e-5: a rounding of the last digit, not a drawn base)
SHARP_GAP = 1e-4
# A base's end is one of its two corners (SPEC 9) where the wall turns there by at least this
# many degrees; a closing segment that turns by less at one end continues that surface
BASE_CORNER = 45.0
# A base drawn as part of a closed ring is a straight piece between two corners: no vertex
# along it turns by this many degrees or more
STRAIGHT_TURN = 5.0


def naca4(code: str, points: int = 201, te: str = "sharp") -> np.ndarray:
    """NACA 4-digit section ``code`` (e.g. "0012", "2412"), chord 1 from (0, 0) to (1, 0),
    ``points`` per surface on a cosine spacing, in Selig order."""
    code = str(code).strip()
    if not re.fullmatch(r"\d{4}", code):
        raise InputError(f"NACA code {code!r}: give four digits, e.g. 0012 or 2412 ({{naca}})")
    m, p, t = int(code[0]) / 100, int(code[1]) / 10, int(code[2:]) / 100
    if t <= 0:
        raise InputError(f"NACA {code}: the thickness (last two digits) must be above 0 ({{naca}})")
    if m > 0 and p == 0:
        raise InputError(
            f"NACA {code}: a cambered section needs the camber position (second "
            "digit) above 0 ({naca})"
        )
    if te not in ("sharp", "blunt"):
        raise ValueError(f"te must be sharp or blunt, not {te!r}")
    beta = np.linspace(0.0, np.pi, points)
    x = 0.5 * (1 - np.cos(beta))
    a4 = -0.1036 if te == "sharp" else -0.1015
    yt = 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 + a4 * x**4)
    if m > 0:
        front = x < p
        yc = np.where(
            front, m / p**2 * (2 * p * x - x**2), m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x**2)
        )
        dyc = np.where(front, 2 * m / p**2 * (p - x), 2 * m / (1 - p) ** 2 * (p - x))
    else:
        yc, dyc = np.zeros_like(x), np.zeros_like(x)
    th = np.arctan(dyc)
    upper = np.column_stack([x - yt * np.sin(th), yc + yt * np.cos(th)])
    lower = np.column_stack([x + yt * np.sin(th), yc - yt * np.cos(th)])
    if te == "sharp":
        upper[-1] = lower[-1] = (1.0, 0.0)
    return np.concatenate([upper[::-1], lower[1:]])


@dataclass(frozen=True)
class Body:
    """A closed body curve: ``surface`` (Selig order, upper trailing edge to lower trailing
    edge, at least ``MIN_POINTS``), whether its trailing edge is ``sharp`` (the two ends coincide)
    and where it came from. Without a base, a blunt trailing edge is closed by the straight
    segment between the surface's two ends. ``cut``: the point where the two surfaces of
    the input crossed near the trailing edge, there cut and closed (SPEC 9), or None;
    ``continued``: "upper" or "lower" where the segment closing the input continued that
    surface (:func:`close_continued`), or None; ``rounded``: a closed curve with no corner
    (a round trailing edge, as a circular root section), started at its point of largest
    x."""

    surface: np.ndarray
    sharp: bool
    source: str
    cut: tuple[float, float] | None = None  # where crossing surfaces were cut and closed
    continued: str | None = None  # the surface a closing segment continues (no base)
    rounded: bool = False  # a closed curve without a corner: no trailing edge to leave

    @property
    def chord_points(self) -> tuple[np.ndarray, np.ndarray]:
        """Leading edge (farthest surface point from the trailing edge) and trailing edge."""
        te = 0.5 * (self.surface[0] + self.surface[-1])
        le = self.surface[int(np.argmax(np.linalg.norm(self.surface - te, axis=1)))]
        return le, te

    @property
    def chord(self) -> float:
        le, te = self.chord_points
        return float(np.linalg.norm(te - le))

    @property
    def mid_chord(self) -> np.ndarray:
        le, te = self.chord_points
        return 0.5 * (le + te)

    @property
    def te_gap(self) -> float:
        return float(np.linalg.norm(self.surface[0] - self.surface[-1]))

    def ring(self) -> np.ndarray:
        """The closed curve, counter-clockwise from the trailing edge, first point repeated
        last (a blunt edge starts and ends at the middle of its base)."""
        s = self.surface
        if self.sharp:
            return np.concatenate([s[:-1], s[:1]])
        mid = 0.5 * (s[0] + s[-1])
        return np.concatenate([mid[None], s, mid[None]])


def _segment_crossings(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the polylines ``a`` (n, 2) and ``b`` (m, 2) cross: the parameters (along a's
    segments, k + t) and (along b's) of every proper crossing, vectorised over the pairs."""
    p, r = a[:-1, None], (a[1:] - a[:-1])[:, None]
    q, s = b[None, :-1], (b[1:] - b[:-1])[None]
    cross = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    d = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (d[..., 0] * s[..., 1] - d[..., 1] * s[..., 0]) / cross
        u = (d[..., 0] * r[..., 1] - d[..., 1] * r[..., 0]) / cross
    hit = (cross != 0) & (t > 0) & (t < 1) & (u > 0) & (u < 1)
    k, m = np.nonzero(hit)
    return k + t[k, m], m + u[k, m]


def cut_crossing(surface: np.ndarray) -> tuple[np.ndarray, tuple[float, float] | None]:
    """A Selig-order surface whose upper and lower surfaces cross (a cusped trailing edge
    whose last point lies above the first): cut at the crossing nearest the leading edge
    and closed there, the loops behind it dropped (SPEC 9); the surface unchanged and None
    where they do not cross."""
    le = int(np.argmin(surface[:, 0]))
    upper, lower = surface[: le + 1], surface[le:]
    tu, tl = _segment_crossings(upper, lower)
    keep = (tu < le - 1) & (tl > 1)  # not the segments that meet at the leading edge
    if not keep.any():
        return surface, None
    k = int(np.argmax(np.where(keep, tu, -1.0)))  # the crossing nearest the leading edge
    iu, fu = int(tu[k]), tu[k] - int(tu[k])
    il = int(tl[k])
    x = upper[iu] + fu * (upper[iu + 1] - upper[iu])
    cut = np.concatenate([x[None], upper[iu + 1 :], lower[1 : il + 1], x[None]])
    return cut, (float(x[0]), float(x[1]))


def _turn(a: np.ndarray, b: np.ndarray) -> float:
    """The angle in degrees between the directions ``a`` and ``b``."""
    cos = float(a @ b) / float(np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def close_continued(surface: np.ndarray) -> tuple[np.ndarray, str | None]:
    """An open Selig-order surface whose closing segment (from the lower end to the upper
    end) continues one surface, turning by less than ``BASE_CORNER`` from it, and meets the
    other at a corner (a lower surface drawn ending short of the upper, along the chord):
    no base, whose ends are two corners (SPEC 9), but that surface's last piece, so the
    trailing edge is the corner, sharp; the wall is the drawn polyline either way. Also
    which surface it continues; the surface unchanged and None otherwise."""
    base = surface[0] - surface[-1]
    lower = _turn(surface[-1] - surface[-2], base)
    upper = _turn(base, surface[1] - surface[0])
    if lower < BASE_CORNER <= upper:
        return np.concatenate([surface, surface[:1]]), "lower"
    if upper < BASE_CORNER <= lower:
        return np.concatenate([surface[-1:], surface]), "upper"
    return surface, None


def _rear_corners(ring: np.ndarray) -> tuple[int, int]:
    """The trailing edge of a closed counter-clockwise ring, from its shape: the indices
    (lower end, upper end) of its rear-most corner (a vertex turning by at least
    ``BASE_CORNER``; a sharp edge, the two equal) or, where the next corner along the ring
    follows it, or it follows the previous one, along a straight piece facing downstream
    (a blunt base drawn as part of the ring, whose middle is where some files start), that
    base's two corners. (-1, -1)
    where the ring has no corner: a round trailing edge."""
    n = len(ring)
    e_in = ring - np.roll(ring, 1, axis=0)
    e_out = np.roll(ring, -1, axis=0) - ring
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    turn = np.degrees(np.arctan2(cross, np.einsum("ij,ij->i", e_in, e_out)))
    corners = np.flatnonzero(turn >= BASE_CORNER)
    if not len(corners):
        return -1, -1
    rear = int(corners[np.argmax(ring[corners, 0])])

    def base_to(k: int, step: int) -> int | None:
        """The corner reached from ``k`` along a straight piece (step +1: forward) that
        faces downstream: its outward normal within ``BASE_CORNER`` of +x."""
        j = k
        while True:
            nxt = (j + step) % n
            if nxt == k:
                return None
            if turn[nxt] >= BASE_CORNER:
                up = (ring[nxt] - ring[k]) * step  # counter-clockwise: lower to upper
                normal = np.array([up[1], -up[0]]) / max(float(np.linalg.norm(up)), 1e-300)
                return nxt if normal[0] >= np.cos(np.radians(BASE_CORNER)) else None
            if abs(turn[nxt]) >= STRAIGHT_TURN:
                return None
            j = nxt

    # counter-clockwise, a base runs from its lower corner to its upper one
    upper, lower = base_to(rear, 1), base_to(rear, -1)
    found = ([(rear, upper)] if upper is not None else []) + (
        [(lower, rear)] if lower is not None else []
    )
    if not found:
        return rear, rear
    # the base whose other corner lies farther back
    return max(found, key=lambda ab: ring[ab[0], 0] + ring[ab[1], 0])


def _from_trailing_edge(ring: np.ndarray) -> tuple[np.ndarray, bool]:
    """A closed counter-clockwise ring as a Selig-order surface: from the upper end of its
    trailing edge (:func:`_rear_corners`) round to the lower end, the base between them
    left out (a sharp edge: the ring from its corner, closed); and whether the edge is
    round (no corner: the ring from its point of largest x)."""
    lower, upper = _rear_corners(ring)
    rounded = lower < 0
    if rounded:
        lower = upper = int(np.argmax(ring[:, 0]))
    rolled = np.roll(ring, -upper, axis=0)
    if lower == upper:
        return np.concatenate([rolled, rolled[:1]]), rounded
    return rolled[: (lower - upper) % len(ring) + 1], rounded


def body_from_points(xy: np.ndarray, source: str, sharp_tol: float = SHARP_GAP) -> Body:
    """A :class:`Body` from airfoil-like points in either orientation, starting anywhere
    near the trailing edge: reordered to Selig order (counter-clockwise, from the point of
    largest x). A closed ring (last point = first) is accepted; ends at most ``sharp_tol``
    of the chord apart are one sharp trailing edge, closed at their mean point; surfaces
    that cross near the trailing edge are cut at the crossing (:func:`cut_crossing`, SPEC 9)."""
    xy = np.asarray(xy, dtype=float)
    if xy.ndim != 2 or xy.shape[1] < 2 or len(xy) < MIN_POINTS:
        raise InputError(f"a body needs at least {MIN_POINTS} points (x y)", source)
    xy = xy[:, :2]
    keep = np.r_[True, np.linalg.norm(np.diff(xy, axis=0), axis=1) > 0]
    xy = xy[keep]
    size = float(np.ptp(xy, axis=0).max())
    if size <= 0:
        raise InputError("all body points coincide", source)
    closed = np.linalg.norm(xy[0] - xy[-1]) <= sharp_tol * size
    if closed:  # a nearly closed trailing edge: both ends at their mean point
        xy = xy.copy()
        xy[0] = xy[-1] = 0.5 * (xy[0] + xy[-1])
    ring = xy[:-1] if closed else xy
    # orientation: counter-clockwise (signed area of the closed curve)
    x, y = ring[:, 0], ring[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if abs(area) <= 1e-9 * size**2:
        raise InputError("the body encloses no area", source)
    if area < 0:
        ring = ring[::-1]
    rounded = False
    if closed:  # the trailing edge found from the shape, wherever the file starts
        surface, rounded = _from_trailing_edge(ring)
    else:  # an open trailing edge: the ends are the two trailing-edge points, and the
        surface = ring  # counter-clockwise ring starts on the upper surface (Selig)
    surface, cut = cut_crossing(surface)
    sharp = bool(np.linalg.norm(surface[0] - surface[-1]) <= sharp_tol * size)
    continued = None
    if not sharp:
        surface, continued = close_continued(surface)
        sharp = continued is not None
    if not sharp:  # a gap whose ends are no corners is a gap in a round edge
        base = surface[0] - surface[-1]
        turns = _turn(surface[-1] - surface[-2], base), _turn(base, surface[1] - surface[0])
        rounded = rounded or max(turns) < BASE_CORNER
    return Body(surface, sharp, source, cut, continued, rounded and cut is None)


def load_body(
    path: str | os.PathLike | None = None, naca: str | None = None, te: str | None = None
) -> Body:
    """The body of a ``.dat`` file or of a NACA code (``te``: sharp or blunt, default sharp)."""
    if naca is not None:
        return body_from_points(naca4(naca, te=te or "sharp"), f"NACA {naca}")
    if path is None:
        raise InputError("give an airfoil file or a NACA code ({naca})")
    if Path(path).suffix.lower() in (".dat", ".txt", ".csv", ""):
        xy, _ = read_dat(path)
        return body_from_points(xy, str(path))
    raise InputError("an airfoil body is read from a Selig or Lednicer .dat file", str(path))


def inside_polygon(pts: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Whether each point (P, 2) lies inside the closed polyline ``ring`` (n, 2): the even-odd
    rule, counting the edges a ray in +x crosses (vectorised over points and edges)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    x, y = pts[:, :1], pts[:, 1:]
    spans = (a[:, 1] > y) != (b[:, 1] > y)  # the edge straddles the point's height
    with np.errstate(divide="ignore", invalid="ignore"):
        at = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return (spans & (x < at)).sum(axis=1) % 2 == 1


@dataclass(frozen=True)
class FarField:
    """A circle (``radius`` about ``center``) or a closed counter-clockwise polyline."""

    center: np.ndarray
    radius: float | None = None
    polyline: np.ndarray | None = None

    def contains(self, pts: np.ndarray) -> np.ndarray:
        if self.radius is not None:
            return np.linalg.norm(pts - self.center, axis=1) < self.radius
        return inside_polygon(pts, self.polyline)


def circle(body: Body, radius: float) -> FarField:
    """Far field: circle of ``radius`` chords about the body's mid-chord."""
    if not (np.isfinite(radius) and radius > 0):
        raise InputError(
            f"far-field radius {radius}: must be a positive number of chords ({{farfield}})"
        )
    if radius < 1.0:
        raise InputError(f"far-field radius {radius}: must be at least 1 chord ({{farfield}})")
    far = FarField(center=body.mid_chord, radius=float(radius) * body.chord)
    if not far.contains(body.surface).all():
        raise InputError(
            f"the far-field circle of radius {radius} chords does not enclose "
            "the body; give a larger radius ({farfield})",
            body.source,
        )
    return far


def polyline_farfield(points: np.ndarray, body: Body, source: str) -> FarField:
    """Far field from a closed polyline, which must enclose the body."""
    pts = np.asarray(points, dtype=float)[:, :2]
    if np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    x, y = pts[:, 0], pts[:, 1]
    if 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) < 0:
        pts = pts[::-1]
    far = FarField(center=body.mid_chord, polyline=pts)
    if not far.contains(body.surface).all():
        raise InputError("the far field (outer closed polyline) does not enclose the body", source)
    return far


__all__ = [
    "Body",
    "FarField",
    "body_from_points",
    "circle",
    "close_continued",
    "cut_crossing",
    "load_body",
    "naca4",
    "polyline_farfield",
    "read_dat",
    "xy_blocks",
]
