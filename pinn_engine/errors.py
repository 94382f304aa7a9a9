"""Exceptions and warnings that carry a one-line, user-facing message."""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Iterable

_ARGUED = re.compile(r"\{(\w+):([^{}]*)\}")  # a token with its argument, {method:elliptic}


class PinnMeshError(Exception):
    """Any failure pinn-mesh reports to a user as one line (CLI exit status 2)."""


class InputError(PinnMeshError, ValueError):
    """Bad boundary, auxiliary line or option; the message names the problem and the source.

    Also a ``ValueError``, as scikit-learn's input errors are: ``except ValueError`` catches
    every bad input, ``except InputError`` the same ones and no programming error.

    A fix that differs between routes is written as a token of ``ROUTE_WORDS`` (e.g.
    ``{corners}``; one whose words hold ``{}`` takes its argument after a colon,
    ``{method:elliptic}``); the message reads in the command line's words, :meth:`for_route`
    gives the same error in another route's words.
    """

    def __init__(self, message: str, source: str | None = None) -> None:
        self.template, self.source = message, source
        super().__init__(self._text("cli"))

    def _text(self, route: str) -> str:
        route_words = ROUTE_WORDS[route]
        text = _ARGUED.sub(
            lambda m: route_words[m[1]].format(m[2]) if m[1] in route_words else m[0],
            self.template,
        )
        for key, words in route_words.items():
            text = text.replace("{" + key + "}", words)
        return f"{self.source}: {text}" if self.source else text

    def for_route(self, route: str) -> InputError:
        """This error worded for ``route``: "cli", "pyvista" or "paraview"."""
        error = type(self)(self.template, self.source)
        error.args = (self._text(route),)
        return error


class SettingsError(InputError):
    """A setting's value is refused: out of its range, an unknown name, or two settings that
    do not go together (the VTK filters' lines begin "invalid settings")."""


def unknown_name(
    name: str, known: Iterable[str], what: str, form: str = "{}", also: Iterable[str] = ()
) -> SettingsError:
    """The error for an unknown ``what`` (a keyword, a setting) called ``name``: the nearest
    of the ``known`` names (or of ``also``, names valid but not listed) suggested, then the
    ``known`` ones listed, each written as ``form`` (``"{}="`` for keyword arguments)."""
    known = list(known)
    nearest = difflib.get_close_matches(name, [*known, *also], n=1)
    hint = f"did you mean {form.format(nearest[0])}? " if nearest else ""
    listing = ", ".join(form.format(k) for k in known)
    return SettingsError(f"unknown {what} {form.format(name)}; {hint}the {what}s: {listing}")


def unknown_keyword(name: str, known: Iterable[str], function: str) -> KeywordError:
    """The error for an unknown keyword ``name`` of the public ``function`` (as users call
    it): the nearest of the ``known`` keywords suggested, else where they are listed."""
    nearest = difflib.get_close_matches(name, list(known), n=1)
    hint = f"did you mean {nearest[0]}=?" if nearest else f"help({function}) lists them"
    return KeywordError(f"{function}: unknown keyword {name}=; {hint}")


class MissingExtraError(PinnMeshError, ImportError):
    """A part of pinn-mesh whose optional dependencies (a pip extra of pyproject.toml) are
    not installed; the one-line message names the extra to install (``source``: what the
    message is about, as ``InputError``'s). ``paraview``: the fix inside ParaView instead,
    whose Python takes no pip install (:meth:`for_route`)."""

    def __init__(
        self, what: str, extra: str, source: str | None = None, paraview: str | None = None
    ) -> None:
        self.what, self.extra, self.source, self.paraview = what, extra, source, paraview
        super().__init__(self._prefixed(f"needs the {extra} extra: {install_extra(extra)}"))

    def _prefixed(self, fix: str) -> str:
        text = f"{self.what} {fix}"
        return f"{self.source}: {text}" if self.source else text

    def for_route(self, route: str) -> MissingExtraError:
        """This error worded for ``route`` (only ParaView's words differ)."""
        error = type(self)(self.what, self.extra, self.source, self.paraview)
        if route == "paraview" and self.paraview:
            error.msg = self._prefixed(f"needs {self.paraview}")  # what str() shows
            error.args = (error.msg,)
        return error


def install_extra(extra: str) -> str:
    """The pip command that installs the extra ``extra``."""
    return f"pip install 'pinn-mesh[{extra}]'"


class KeywordError(PinnMeshError, TypeError):
    """An unknown keyword argument of a public function: a ``TypeError``, as Python and
    pyvista raise for one, with the nearest keyword suggested."""


class TrainingError(PinnMeshError):
    """Training diverged or was cancelled; no grid is produced."""


class NotFittedError(PinnMeshError, AttributeError):
    """A ``Mesher`` used before ``fit`` (scikit-learn's convention)."""


class TrainingCancelled(TrainingError):
    """The progress callback asked training to stop (answered True)."""


# A progress callback's other answer: end the training now and make the grid of the best state
# so far (a warning says so), as a time limit does; no grid is lost to a stop
STOP = "stop"


class JetKernelsWarning(UserWarning):
    """The C++ jet kernels are not used (no compiler, or their build failed): the networks'
    jets run as torch operations, the same results, slower. A Python warning, so that
    ``warnings.filterwarnings("ignore", category=JetKernelsWarning)`` (or ``-W``) quiets
    it; the command line's ``--quiet`` does."""


class WallAngleWarning(UserWarning):
    """A grid was produced although its lines leave an orthogonal side (SPEC 7) more than
    ``WALL_ANGLE_TOL`` degrees off 90 (pyvista route); filter it like any warning."""


class FamilyFallbackWarning(UserWarning):
    """A family model's grid failed the guard (a fold, or a worst cell above the member's
    own start's + 2 degrees; SPEC 16): the member's own start was produced instead."""


class TrainingStoppedWarning(UserWarning):
    """A grid was produced from a training stopped early, by ``time_limit`` or a progress
    callback's ``STOP`` answer (pyvista route): the best state so far."""


class CrossingCutWarning(UserWarning):
    """The body's upper and lower surfaces crossed near the trailing edge and were cut at
    the crossing and closed there (SPEC 9): the grid's wall ends there (pyvista route)."""


class FoldedCellsWarning(UserWarning):
    """A grid was produced although some of its cells are folded (pyvista route).

    Filter it like any warning, e.g. ``warnings.simplefilter("error", FoldedCellsWarning)``
    to refuse such grids or ``"ignore"`` to accept them silently.
    """


# Fixes worded for each route ("cli", "pyvista", "paraview": command-line options, pyvista
# keyword arguments, the ParaView panel's labels), by token; each route's words are its own
# (``routes.names``, which registers them here when ``pinn_engine`` is imported)
ROUTE_WORDS: dict[str, dict[str, str]] = {"cli": {}, "pyvista": {}, "paraview": {}}


def register_route_words(route: str, words: dict[str, str]) -> None:
    """Give ``route``'s words to the tokens of ``InputError`` templates."""
    ROUTE_WORDS[route] = dict(words)


_HANDED_OVER = {"cli": "written", "pyvista": "returned", "paraview": "produced"}


def _folded_parts(report: dict) -> tuple[str, str] | None:
    """What is folded and the fix (a template of ``ROUTE_WORDS`` tokens) of a grid with
    folded cells, or None when no cell is folded; ``report`` as :func:`folded_cells_warning`
    takes it."""
    folded = int(report["quality"]["folded_cells"])
    if folded <= 0:
        return None
    cells = report.get("cells") or math.prod(n - 1 for n in report["size"])
    method = report.get("method", "")
    training = report.get("training", {})
    guard = training.get("guard") or {}
    parts = [training, *training.get("blocks", [])]
    forced = next(
        (p["untangled"]["forced"] for p in parts if "forced" in p.get("untangled", {})), None
    )
    if forced:  # the boundary nodes themselves fold a cell (untangle.fold_forced)
        fix = (
            "rounding the boundary there or another {size}: no grid on these "
            f"boundary nodes is fold-free, as {forced}"
        )
    elif guard.get("elliptic", {}).get("folded_cells"):  # the warm start's elliptic grid folds too
        fix = (
            "rounding the boundary where it turns sharply between nodes or another "
            "{size}: the converged elliptic grid on these boundary nodes folds "
            f"{guard['elliptic']['folded_cells']} cells as well"
        )
    elif method == "tfi":
        fix = "{method:elliptic}"
    elif method == "elliptic" and report.get("settings", {}).get("elliptic_iterations"):
        fix = "{converge} or {method:pinn}"
    elif method == "elliptic":
        fix = "{method:pinn}"
    else:  # a method that trains a network
        fix = "{method:elliptic}, {lbfgs} or {seed}"
    verb = "is" if folded == 1 else "are"
    what = f"{folded} of {cells} cells {verb} folded (a corner's orientation opposes the grid's)"
    return what, fix


def folded_cells_warning(report: dict, route: str) -> str | None:
    """The warning for a grid with folded cells, or None when no cell is folded.

    ``report`` is ``MeshResult.report`` or a hexahedral grid's (its ``quality.folded_cells``,
    ``cells`` or ``size``, ``method`` and ``settings``); ``route`` is ``"cli"``,
    ``"pyvista"`` or ``"paraview"`` and chooses the words of the hint: options, keyword
    arguments or the filter panel's labels. Each route adds its own prefix (``pinn-mesh:
    warning:``, the filter's label, the warning category). A 2D grid with folded cells is
    refused instead (:func:`folded_cells_refusal`).
    """
    found = _folded_parts(report)
    if found is None:
        return None
    what, fix = found
    text = f"{what}; the grid is {_HANDED_OVER[route]} anyway; try {fix}{{refuse}}"
    return InputError(text)._text(route)


def folded_cells_refusal(report: dict, source: str | None) -> InputError | None:
    """The refusal of a 2D grid with folded cells (a grid handed over covers the domain with
    no fold), the fix in the route's words; None when no cell is folded."""
    found = _folded_parts(report)
    if found is None:
        return None
    what, fix = found
    return InputError(f"the grid is not written: {what}; try {fix}", source)


def stopped_training_warning(report: dict, route: str) -> str | None:
    """The warning for a grid from a training that ended early (``training.stopped`` of the
    report: its time limit ran out, or a stop was asked), or None; words as
    :func:`folded_cells_warning`."""
    stopped = report.get("training", {}).get("stopped")
    if not stopped:
        return None
    where = f"during {stopped['phase']} at step {stopped['step']}"
    if stopped["reason"] == "time limit":
        why = f"its time limit of {stopped['time_limit']:g} s ran out {where}"
        fix = f"; for the full training give {ROUTE_WORDS[route]['time_limit']}"
    else:
        why, fix = f"a stop was asked {where}", ""
    return (
        f"training stopped after {stopped['seconds']:g} s ({why}); the grid of the best "
        f"state so far is {_HANDED_OVER[route]}{fix}"
    )


WALL_ANGLE_TOL = 2.0  # SPEC 7: degrees off 90, the two nodes nearest each corner aside


def wall_angle_warning(report: dict, route: str) -> str | None:
    """The warning for a grid whose lines leave a side asked to be orthogonal (SPEC 7) more
    than ``WALL_ANGLE_TOL`` degrees off 90, or None; words as :func:`folded_cells_warning`."""
    sides = report.get("settings", {}).get("orthogonal") or ()
    figures = report.get("sides", {})
    off = {
        side: figures[side]["max_angle_deviation"]
        for side in sides
        if side in figures and figures[side]["max_angle_deviation"] > WALL_ANGLE_TOL
    }
    if not off:
        return None
    listing = ", ".join(f"{side} {angle:.1f}" for side, angle in off.items())
    return (
        f"grid lines leave orthogonal sides more than {WALL_ANGLE_TOL:g} degrees off 90 "
        f"({listing} degrees; the two nodes nearest each corner aside); the grid is "
        f"{_HANDED_OVER[route]} anyway; where a wall turns sharply within a cell, round it or "
        f"try another {ROUTE_WORDS[route]['size']}"
    )


def network_effect(report: dict) -> str | None:
    """What the default chose, for the summary line of every route (and the report's
    ``choice``): the grid returned (the network's, or the start it kept: the elliptic grid,
    the quality objective's, ...), whether a network was trained and for how long, and the
    worst cell of the grid returned against the elliptic grid's on the same boundary nodes;
    None for a method without network."""
    training = report.get("training")
    if not training or ("result" not in training and "blocks" not in training):
        return None
    start = training.get("start", "elliptic")
    worst = report.get("quality", {}).get("worst_max_angle")
    elliptic = ((training.get("guard") or {}).get("elliptic") or {}).get("worst_max_angle")
    gain = (
        f"; worst cell {worst:.2f} deg, the elliptic grid's {elliptic:.2f}"
        if worst is not None and elliptic is not None
        else ""
    )
    if "blocks" in training:  # a multi-block grid's blocks
        return _blocks_choice(training, gain)
    resize = report.get("resized")
    if resize and resize["result"] == "network":  # a network trained at another size
        (ti, tj), (ni, nj) = resize["trained_at"], resize["size"]
        start = resize["guard"]["start"]["worst_max_angle"]  # this size's start: its guard's
        gain = "" if worst is None else f"; worst cell {worst:.2f} deg, the start's {start:.2f}"
        return (
            f"chose the network trained at {ti} x {tj}, evaluated at {ni} x {nj} (a forward "
            f"pass; this size's guard passed, no training){gain}"
        )
    if "model" in training:  # a family model's grid (SPEC 16)
        if training["result"] == "start":
            return (
                f"family model {training['model']}: the member's {start} start kept (guard){gain}"
            )
        steps = training.get("winslow_steps")
        done = f", then {steps} linearised Winslow steps" if steps else ""
        return f"family model {training['model']}: its grid kept (a forward pass{done}){gain}"
    if training.get("skipped"):
        return f"chose the {start} grid{gain} (no network trained: {training['skipped']})"
    seconds = report.get("train_seconds", (training.get("timings") or {}).get("training", 0.0))
    anew = ""
    if resize:  # the network trained at another size failed this one's guard
        (ti, tj) = resize["trained_at"]
        anew = f"; the network trained at {ti} x {tj} failed this size's guard: {resize['why']}"
    if training["result"] == "start":
        return (
            f"chose the {start} grid{gain} (the network trained {seconds:.2f} s; no trained "
            f"state passed the quality guard{anew})"
        )
    move = training.get("largest_node_move")
    moved = "" if move is None else f", nodes moved up to {move:.1e} of the diagonal"
    origin = "TFI" if move is None else f"the {start} grid"
    return f"chose the network's grid (trained {seconds:.2f} s from {origin}{moved}{anew}){gain}"


def _blocks_choice(training: dict, gain: str) -> str:
    """:func:`network_effect` of a multi-block grid: in how many blocks the network's grid
    was kept, the elliptic grid (untangled where it folds) elsewhere, and ``gain``."""
    blocks = training["blocks"]
    kept = training.get("network_blocks", 0)
    untangled = sum("untangled" in b for b in blocks)
    start = training.get("start", "elliptic")
    elliptic = f"the {start} grid{f' (untangled in {untangled})' if untangled else ''}"
    if kept:
        return (
            f"chose the network's grid in {kept} of {len(blocks)} blocks, {elliptic} elsewhere "
            f"(trained {training['seconds']:.2f} s){gain}"
        )
    reasons = {b.get("skipped") for b in blocks}
    why = (
        f" (no network trained: {reasons.pop()})"
        if len(reasons) == 1 and None not in reasons
        else ""
    )
    return f"chose {elliptic} in every block{gain}{why}"


def family_fallback_warning(report: dict, route: str) -> str | None:  # noqa: ARG001
    """The warning for a member whose family model's grid was not kept (the report's
    ``training.fallback``; a multi-block member's ``family.fallback``), or None; the same
    words on every route."""
    return report.get("training", {}).get("fallback") or (report.get("family") or {}).get(
        "fallback"
    )


def crossing_cut_warning(report: dict, route: str) -> str | None:
    """The warning for a body whose crossing surfaces were cut (``report["topology"]["cut"]``,
    the crossing's x, y), or None; the same words on every route."""
    cut = (report.get("topology") or {}).get("cut")
    if not cut:
        return None
    return (
        f"the upper and lower surfaces cross near the trailing edge: cut at the crossing "
        f"(x = {cut[0]:.6g}, y = {cut[1]:.6g}) and closed there"
    )


def grid_warnings(report: dict, route: str) -> list[tuple[str, type[UserWarning]]]:
    """Every warning a produced grid carries, in ``route``'s words, with the category the
    pyvista route warns with: crossing surfaces cut, a stopped training, folded cells, lines
    off an orthogonal side."""
    found = (
        (crossing_cut_warning(report, route), CrossingCutWarning),
        (stopped_training_warning(report, route), TrainingStoppedWarning),
        (folded_cells_warning(report, route), FoldedCellsWarning),
        (wall_angle_warning(report, route), WallAngleWarning),
        (family_fallback_warning(report, route), FamilyFallbackWarning),
    )
    return [(text, category) for text, category in found if text]
