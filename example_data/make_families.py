"""Families of shapes for the family models (SPEC 16, docs/family.md), with their manifests.

``.venv/bin/python example_data/make_families.py OUTDIR [--train N] [--unseen N] [--seed S]``
writes, for each family, ``OUTDIR/<family>/`` with one input file a member and two manifests
(SPEC 12): ``train.csv`` and ``unseen.csv`` (members drawn from the same ranges, none of them a
training member). ``--wide`` draws the unseen members from ranges 25 % wider on each side, to
measure how the error grows outside the training ranges.

- ``channels``: a channel of length 3 and height 1 with a Gaussian bump on its floor (height,
  centre, width) and a waving roof (amplitude, wavelength, phase), meshed at 41 x 21.
- ``channels_winslow``: the same channels meshed by the Winslow objective (``--objective
  winslow``): a family of Winslow grids.
- ``naca``: NACA 4-digit-like sections (camber, its position and thickness as real numbers, the
  4-digit formula's blunt trailing edge) as Selig ``.dat`` files, O-grids at 129 x 41.
- ``naca_c``: the same sections with the modified formula's closed trailing edge, C-grids at
  129 x 41.
- ``cylinder``: the DFG 2D-1 channel with its cylinder moved and resized (centre, radius), in
  the blocking of ``dfg_blocks.vtp`` (``make_multiblock.dfg``: 12 blocks), each member's block
  edges beside it and its chains' cell counts fixed by ``--cells`` (``CYLINDER_CELLS``).
"""

from __future__ import annotations

import argparse
import csv
from collections.abc import Callable
from pathlib import Path

import numpy as np

# Parameter ranges (low, high) of each family: wide enough that the members differ visibly,
# narrow enough that every member meshes without a fold by the default run.
CHANNEL_RANGES = {
    "bump_height": (0.08, 0.3),
    "bump_centre": (1.1, 1.9),
    "bump_width": (0.2, 0.45),
    "roof_amplitude": (0.02, 0.1),
    "roof_waves": (1.0, 3.0),
    "roof_phase": (0.0, 2 * np.pi),
}
NACA_RANGES = {"camber": (0.0, 0.06), "camber_at": (0.25, 0.6), "thickness": (0.08, 0.2)}
CHANNEL_LENGTH, CHANNEL_HEIGHT = 3.0, 1.0
CHANNEL_OPTIONS, NACA_OPTIONS = "--size 41 21", "--topology o --size 129 41"
NACA_C_OPTIONS = "--topology c --size 129 41"
# The cylinder's centre and radius in the DFG channel [0, 2.2] x [0, 0.41] (DFG 2D-1: (0.2,
# 0.2), 0.05), the square of half side 0.1 around it inside the channel at 25 % wider ranges
CYLINDER_RANGES = {"centre_x": (0.15, 0.3), "centre_y": (0.16, 0.25), "radius": (0.035, 0.06)}
# Cells along each chain of the blocking (upstream, along each side of the square, downstream,
# below and above it, cylinder to square): the same in every member, as a family's counts
# are; cells about 0.017 across the square's rows, 0.033 long downstream
CYLINDER_CELLS = {"upstream": 6, "square": 12, "downstream": 60, "radial": 8, "below": 6}
# The thickness formula's x^4 coefficient: the classical one leaves a blunt trailing edge
# (0.21 % of the thickness), which a C-grid refuses; the modified one closes it
BLUNT_A4, SHARP_A4 = -0.1015, -0.1036
WIDER = 0.25  # --wide: each range grows by this share of its width on each side
SIDE_POINTS = 161  # points on each curved side (the inputs are polylines: dense enough to be smooth
SURFACE_POINTS = 121  # points on each airfoil surface, cosine-spaced


def draw(ranges: dict, rng: np.random.Generator, wide: bool = False) -> dict:
    """One member's parameters, uniform in ``ranges`` (widened by ``WIDER`` with ``wide``)."""
    out = {}
    for name, (low, high) in ranges.items():
        grow = WIDER * (high - low) if wide and name != "roof_phase" else 0.0
        out[name] = float(rng.uniform(low - grow, high + grow))
    return out


def channel(p: dict) -> np.ndarray:
    """The counter-clockwise ring of a bump-and-roof channel from (0, 0)."""
    x = np.linspace(0.0, CHANNEL_LENGTH, SIDE_POINTS)
    floor = p["bump_height"] * np.exp(-(((x - p["bump_centre"]) / p["bump_width"]) ** 2))
    wave = 2 * np.pi * p["roof_waves"] / CHANNEL_LENGTH
    roof = CHANNEL_HEIGHT + p["roof_amplitude"] * np.sin(wave * x + p["roof_phase"])
    bottom = np.column_stack([x, floor])
    top = np.column_stack([x, roof])[::-1]
    right = np.linspace(bottom[-1], top[0], 21)
    left = np.linspace(top[-1], bottom[0], 21)
    return np.vstack([bottom[:-1], right[:-1], top[:-1], left[:-1]])


def naca_like(p: dict, closing: float = BLUNT_A4) -> np.ndarray:
    """A NACA 4-digit-like section (chord 1, a blunt trailing edge; with ``SHARP_A4`` a
    closed one), Selig order."""
    m, k, t = p["camber"], p["camber_at"], p["thickness"]
    x = 0.5 * (1 - np.cos(np.linspace(0.0, np.pi, SURFACE_POINTS)))
    yt = 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 + closing * x**4)
    yc = np.where(
        x < k, m / k**2 * (2 * k * x - x**2), m / (1 - k) ** 2 * (1 - 2 * k + 2 * k * x - x**2)
    )
    dyc = np.where(x < k, 2 * m / k**2 * (k - x), 2 * m / (1 - k) ** 2 * (k - x))
    th = np.arctan(dyc)
    upper = np.column_stack([x - yt * np.sin(th), yc + yt * np.cos(th)])
    lower = np.column_stack([x + yt * np.sin(th), yc - yt * np.cos(th)])
    return np.concatenate([upper[::-1], lower[1:]])


def naca_closed(p: dict) -> np.ndarray:
    """:func:`naca_like` with the closed trailing edge a C-grid's wake cut leaves from."""
    return naca_like(p, SHARP_A4)


def write_vtp(points: np.ndarray, path: Path) -> None:
    """A closed polyline as ``.vtp``."""
    from make_examples import polydata
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(polydata([points], closed=True))
    writer.Write()


def write_dat(points: np.ndarray, path: Path, title: str) -> None:
    """Selig ``.dat``: a title line, then x y rows."""
    rows = "\n".join(f"{x:.7f} {y:.7f}" for x, y in points)
    path.write_text(f"{title}\n{rows}\n")


def cylinder_options(p: dict) -> str:
    """The ``--cells`` items that give a cylinder member the family's counts: each chain's
    by a point on one of its sides (each side of the square is a chain of its own, through
    the ring's block and on to a wall, the inlet or the outlet)."""
    from make_multiblock import DFG_BOX, DFG_HEIGHT, DFG_LENGTH

    cx, cy, r = p["centre_x"], p["centre_y"], p["radius"]
    c = CYLINDER_CELLS
    out = 0.5 * (r + DFG_BOX * np.sqrt(2)) / np.sqrt(2)  # mid-way along a diagonal edge
    places = [
        (0.005, 0.0, c["upstream"]),
        (cx, 0.0, c["square"]),
        (DFG_LENGTH - 0.005, 0.0, c["downstream"]),
        (0.0, 0.005, c["below"]),
        (0.0, cy, c["square"]),
        (cx, DFG_HEIGHT, c["square"]),
        (DFG_LENGTH, cy, c["square"]),
        (0.0, DFG_HEIGHT - 0.005, c["below"]),
        (cx + out, cy + out, c["radial"]),
    ]
    return " ".join(f"--cells {x:.6f},{y:.6f}={n}" for x, y, n in places)


def write_cylinder(p: dict, path: Path) -> str:
    """A cylinder member's boundary at ``path`` (``.vtp``) and its block edges beside it
    (``<stem>_blocks.vtp``); its options."""
    from make_examples import polydata
    from make_multiblock import dfg
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    rings, edges = dfg((p["centre_x"], p["centre_y"]), p["radius"])
    blocks = path.with_name(f"{path.stem}_blocks.vtp")
    for target, lines, closed in ((path, rings, True), (blocks, edges, False)):
        writer = vtkXMLPolyDataWriter()
        writer.SetFileName(str(target))
        writer.SetInputData(polydata(lines, closed))
        writer.Write()
    return f"--blocks {blocks.name} {cylinder_options(p)}"


FAMILIES: dict[str, tuple[dict, Callable, str, str]] = {
    "channels": (CHANNEL_RANGES, channel, ".vtp", CHANNEL_OPTIONS),
    "channels_winslow": (CHANNEL_RANGES, channel, ".vtp", f"{CHANNEL_OPTIONS} --objective winslow"),
    "naca": (NACA_RANGES, naca_like, ".dat", NACA_OPTIONS),
    "naca_c": (NACA_RANGES, naca_closed, ".dat", NACA_C_OPTIONS),
    "cylinder": (CYLINDER_RANGES, write_cylinder, ".vtp", ""),
}


def make_family(name: str, out: Path, train: int, unseen: int, seed: int, wide: bool) -> None:
    """Write family ``name``'s members and its two manifests under ``out / name``."""
    ranges, shape, suffix, options = FAMILIES[name]
    folder = out / name
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    for split, count in (("train", train), ("unseen", unseen)):
        rows = []
        for k in range(count):
            params = draw(ranges, rng, wide and split == "unseen")
            member = f"{split}{k:02d}"
            path = folder / f"{member}{suffix}"
            own = options
            if shape is write_cylinder:  # a boundary and its block edges, its own --cells
                own = shape(params, path)
            elif suffix == ".dat":
                write_dat(shape(params), path, member)
            else:
                write_vtp(shape(params), path)
            rows.append({"name": member, "input": path.name, "aux": "", "options": own})
        with (folder / f"{split}.csv").open("w", newline="") as f:
            writer = csv.DictWriter(f, ["name", "input", "aux", "options"])
            writer.writeheader()
            writer.writerows(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir", type=Path)
    parser.add_argument("--train", type=int, default=24)
    parser.add_argument("--unseen", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--wide", action="store_true", help="unseen members from wider ranges")
    parser.add_argument("--family", choices=sorted(FAMILIES), action="append")
    args = parser.parse_args()
    for name in args.family or sorted(FAMILIES):
        make_family(name, args.outdir, args.train, args.unseen, args.seed, args.wide)


if __name__ == "__main__":
    main()
