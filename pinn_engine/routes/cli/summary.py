"""What a run tells on stderr besides its progress: the summary lines and the warnings."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from pinn_engine.errors import network_effect
from pinn_engine.settings import Settings

if TYPE_CHECKING:  # the result's module (numpy, the plane) is loaded by the run, not here
    from pinn_engine.result import MeshResult


def say(text: str) -> None:
    """One line on stderr, flushed (it stands between progress lines)."""
    print(text, file=sys.stderr, flush=True)


def warn(text: str) -> None:
    """A warning line, printed with --quiet too."""
    say(f"pinn-mesh: warning: {text}")


def _quality(grid: str, seconds: float, q: dict) -> str:
    """The summary's start: the grid, its time and its cells' quality."""
    return (
        f"{grid} in {seconds:.2f} s: mean MaxIncludedAngle {q['mean_max_angle']:.2f}, "
        f"worst {q['worst_max_angle']:.2f} deg, {q['folded_cells']} folded cells"
    )


def _aux_lines(distances: dict, diagonal: str) -> None:
    """How close the grid lines came to the auxiliary lines' ``diagonal``, if there are any."""
    if distances:
        say(
            f"auxiliary lines: grid lines within {max(distances.values()):.2e} of {diagonal} "
            "of the drawn lines"
        )


def grid_summary(result: MeshResult, settings: Settings, ni: int, nj: int, seconds: float) -> None:
    """A four-sided grid's or a body's summary: quality, the wall or the sides asked for, the
    auxiliary lines, and what the network did."""
    q = result.quality
    t = result.report.get("topology")
    grid = f"{settings.topology.upper()}-grid" if t else "grid"
    say(
        _quality(f"{settings.method} {ni}x{nj} {grid}", seconds, q)
        + (
            f"; first layer {t['first_layer']['min']:.3g} .. {t['first_layer']['max']:.3g}, "
            f"wall angles within {t['wall_angle_deviation']:.2f} deg of 90"
            if t
            else f", boundary deviation {q['boundary_deviation']:.1e}"
        )
    )
    effect = network_effect(result.report)
    if effect:
        say(effect)
    if t:
        return
    spaced = tuple(k for k, _ in settings.spacing if k not in settings.orthogonal)
    for side in settings.orthogonal + spaced:
        r = result.report["sides"][side]
        say(
            f"{side}: first edges {r['first_edge_min']:.3g}..{r['first_edge_max']:.3g}, "
            f"wall angles within {r['max_angle_deviation']:.2f} deg of 90, growth "
            f"ratio up to {r['max_growth_ratio']:.3f}"
        )
    _aux_lines(result.report["aux_line_distance"], "the diagonal")


def _trained(report: dict) -> str:
    """The multi-block pinn's training in the summary: in how many blocks the network's
    grid was kept (the elliptic block elsewhere) and the training's seconds."""
    training = report.get("training")
    if training is None:
        return ""
    return (
        f"; the network's grid kept in {training['network_blocks']} of {report['blocks']} "
        f"blocks, the elliptic grid elsewhere ({training['seconds']:.2f} s training)"
    )


def blocks_summary(method: str, report: dict, seconds: float) -> None:
    """A multi-block grid's summary: quality, the kinks at the interfaces, what the network
    did and the auxiliary lines."""
    kink = report["interface_kink"]
    say(
        _quality(
            f"{method} {report['blocks']} blocks, {report['cells']} cells",
            seconds,
            report["quality"],
        )
        + f"; grid lines cross interfaces with kinks of {kink['mean']:.2f} deg mean, "
        f"{kink['max']:.2f} max{_trained(report)}"
    )
    blocking = report.get("blocking", {})
    if blocking.get("mode") == "automatic":
        say(f"automatic blocking: {blocking['edges']} block edges in {blocking['seconds']:.2f} s")
    _aux_lines(report["aux_line_distance"], "their block's diagonal")
