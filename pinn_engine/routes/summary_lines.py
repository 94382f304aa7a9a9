"""The summary lines of a run: what the command line prints after a grid and the ParaView
filters show in Output Messages after an Apply (the same words on both routes)."""

from __future__ import annotations

from pinn_engine.errors import network_effect
from pinn_engine.patchnames import FACE_PREFIX
from pinn_engine.settings import Settings


def _quality(grid: str, seconds: float, q: dict) -> str:
    """The summary's start: the grid, its time and its cells' quality."""
    return (
        f"{grid} in {seconds:.2f} s: mean MaxIncludedAngle {q['mean_max_angle']:.2f}, "
        f"worst {q['worst_max_angle']:.2f} deg, {q['folded_cells']} folded cells"
    )


def _aux_lines(distances: dict, diagonal: str, turns: dict | None = None) -> list[str]:
    """How close the grid lines came to the auxiliary lines' ``diagonal``, if there are any,
    and how much the grid lines crossing them turn there."""
    if not distances:
        return []
    crossing = (
        f", the grid lines crossing them turning {max(turns.values()):.2f} deg there (mean, "
        "largest of the lines)"
        if turns
        else ""
    )
    return [
        f"auxiliary lines: grid lines within {max(distances.values()):.2e} of {diagonal} "
        f"of the drawn lines{crossing}"
    ]


def grid_lines(report: dict, settings: Settings, ni: int, nj: int, seconds: float) -> list[str]:
    """A four-sided grid's or a body's summary (of its ``report``): quality, the wall or the
    sides asked for, the auxiliary lines, and what the network did."""
    q = report["quality"]
    t = report.get("topology")
    grid = f"{settings.topology.upper()}-grid" if t else "grid"
    lines = [
        _quality(f"{settings.method} {ni}x{nj} {grid}", seconds, q)
        + (
            f"; first layer {t['first_layer']['min']:.3g} .. {t['first_layer']['max']:.3g}, "
            f"wall angles within {t['wall_angle_deviation']:.2f} deg of 90"
            if t
            else f", boundary deviation {q['boundary_deviation']:.1e}"
        )
    ]
    placed = report.get("boundary_placed")
    if placed:
        lines.append(
            "boundary nodes placed on the boundary: the soft boundary's network reached it "
            f"to {placed['network_deviation']:.1e} of the diagonal"
        )
    effect = network_effect(report)
    if effect:
        lines.append(effect)
    lines += adaptation_lines(report)
    if t:
        return lines
    spaced = tuple(k for k, _ in settings.spacing if k not in settings.orthogonal)
    for side in settings.orthogonal + spaced:
        r = report["sides"][side]
        lines.append(
            f"{side}: first edges {r['first_edge_min']:.3g}..{r['first_edge_max']:.3g}, "
            f"wall angles within {r['max_angle_deviation']:.2f} deg of 90, growth "
            f"ratio up to {r['max_growth_ratio']:.3f}"
        )
    return lines + _aux_lines(
        report["aux_line_distance"], "the diagonal", report.get("aux_line_turn")
    )


def adaptation_lines(report: dict) -> list[str]:
    """What adapting to a field did (SPEC 14), if it was asked: the strength used, the
    field's interpolation error and the equidistribution before and after, the largest move
    and the worst cell."""
    a = report.get("adaptation")
    if not a:
        return []
    cv, error, worst = a["equidistribution_cv"], a["interpolation_error"], a["worst_max_angle"]
    if not a["strength_used"]:
        return [
            f"adapted to {a['array']}: kept unadapted (no strength up to {a['strength']:g} lowered "
            f"the field's interpolation error {error['before']:.3g} within the worst cell's "
            f"bound of {worst['limit']:.1f} deg)"
        ]
    less = (
        f", adapted less than asked ({a['strength']:g}) where the worst cell's bound needs it"
        if a["adapted_less"]
        else ""
    )
    if a.get("moved_within_bound"):
        less += " (nodes moved to the nearest grid within it)"
    return [
        f"adapted to {a['array']} at strength {a['strength_used']:g}{less}: interpolation error "
        f"{error['before']:.3g} -> {error['after']:.3g}, equidistribution CV {cv['before']:.2f} "
        f"-> {cv['after']:.2f}, largest node move {a['largest_node_move']:.3g}, worst "
        f"MaxIncludedAngle {worst['before']:.2f} -> {worst['after']:.2f} deg"
    ]


def blocks_lines(method: str, report: dict, seconds: float) -> list[str]:
    """A multi-block grid's summary: quality, the kinks at the interfaces, what the network
    did and the auxiliary lines."""
    kink = report["interface_kink"]
    first = _quality(
        f"{method} {report['blocks']} blocks, {report['cells']} cells",
        seconds,
        report["quality"],
    ) + (
        f"; grid lines cross interfaces with kinks of {kink['mean']:.2f} deg mean, "
        f"{kink['max']:.2f} max"
    )
    effect = network_effect(report)
    blocking = report.get("blocking", {})
    automatic = (
        [f"automatic blocking: {blocking['edges']} block edges in {blocking['seconds']:.2f} s"]
        if blocking.get("mode") == "automatic"
        else []
    )
    graded = report.get("graded_cells", {})
    raised = (
        [
            f"gradings: {graded['from']} cells from the cell size raised to {graded['to']}, so "
            "that neighbouring cells along each graded chain differ by at most 1.25"
        ]
        if graded.get("to", 0) > graded.get("from", 0)
        else []
    )
    return [
        first,
        *([effect] if effect else []),
        *raised,
        *automatic,
        *adaptation_lines(report),
        *_aux_lines(report["aux_line_distance"], "their block's diagonal"),
    ]


def _kept(report: dict, kept: str | None = None) -> str:
    """The grid a blockMeshDict kept (or ``kept``), a blend with its share of the way to the
    Winslow grid, an optimised section with the grid it started from."""
    kept = kept or report["kept"]
    if kept == "optimised":
        return f"section-optimised {_kept(report, report['start'])}"
    if kept != "blend":
        return kept
    return f"blend ({report['blend']:.2f} of the way from blockMesh's placement to Winslow's)"


def dictionary_line(report: dict) -> str:
    """A blockMeshDict's summary (of its ``report``), one line: the grid kept, blocks,
    cells, patches, checkMesh's figures beside blockMesh's placement, time."""
    q, tfi = report["quality"], report["candidates"]["tfi"]
    patches = ", ".join(f"{n} ({p['type']}, {p['faces']})" for n, p in report["patches"].items())
    return (
        f"{report['method']}: {_kept(report)} grid of {report['blocks']} blocks, "
        f"{report['cells']} cells, patches {patches}; checkMesh non-orthogonality max "
        f"{q['max_non_orthogonality']:.2f} deg (blockMesh's placement "
        f"{tfi['max_non_orthogonality']:.2f}), skewness max {q['max_skewness']:.3f} "
        f"({tfi['max_skewness']:.3f}), {q['folded_cells']} folded, "
        f"{report['timings']['total']:.2f} s"
        + (f" ({report['winslow_steps']} Winslow steps)" if report["winslow_steps"] else "")
    )


def hexa_lines(report: dict) -> list[str]:
    """A hexahedral grid's summary (of its ``report``), a short line each: cells, time, folds
    and the Picard steps; min ScaledJacobian, mean/worst MaxIncludedAngle; each wall asked
    for; which side each input face is (``face3=imin``, in FaceId order: an STL's faces are
    numbered so); what the network did (one line of all was cut by ParaView's Output
    Messages)."""
    ni, nj, nk = report["size"]
    q = report["quality"]
    walls = report.get("walls", {})
    faces = sorted(report["faces"].items(), key=lambda item: item[1])
    effect = network_effect(report) if "training" in report else ""
    first = (
        f"{report['method']} {ni}x{nj}x{nk} hexahedral grid, {report['cells']} cells in "
        f"{report['seconds']:.2f} s: {q['folded_cells']} folded"
        + (f" ({report['iterations']} Picard steps)" if report["iterations"] else "")
    )
    figures = (
        f"min ScaledJacobian {q['min_scaled_jacobian']:.3f}, mean MaxIncludedAngle "
        f"{q['mean_max_angle']:.2f} deg, worst {q['worst_max_angle']:.2f} deg"
    )
    walls_lines = [
        f"{patch}: first edges {w['first_edge']['min']:.3g}..{w['first_edge']['max']:.3g}"
        f", grid lines within {w['max_angle_deviation']:.2f} deg of the normal"
        for patch, w in walls.items()
    ]
    sides = " ".join(f"{FACE_PREFIX}{f}={side}" for side, f in faces)
    faces_lines = [f"faces {sides}"] if faces else []
    return [first, figures, *walls_lines, *faces_lines, *([effect] if effect else [])]
