"""Training only where the network can win: the decision every kind makes, and the one
sequence every kind's pinn runs.

The default pinn's network starts as its start grid and trains the Winslow equations, plus
the terms the user asked for: auxiliary lines to follow, orthogonal sides, a spacing. The
start already solves the Winslow equations on its nodes (the converged elliptic grid, or it
untangled, where nothing better exists on those nodes without folds), and under the quality
objective it is that objective's own optimum on the nodes. Without another term the network
has nothing to win, and its guard has always ended with the start, or with a state that moves
nodes by discretisation error only (docs/speed.md). :func:`cannot_win` says so before any
network is built or torch imported; the block's map is then its start (each kind's
``untrained`` module: ``four_sided.untrained.StartModel``, ``hexa.untrained.VolumeStartModel``
for a six-faced 3D block, whose network trains the 3D Winslow equations alone unless a patch
has a spacing or is orthogonal; ``blocks.untrained`` for each block of a multi-block grid;
``body.untrained`` for an O- or C-grid), the map a trained model has with its output layer at
zero.

Every kind runs the same sequence once its start is known, :func:`start_or_train`: where the
network cannot win, the start is kept; else the kind's training module (torch) is imported and
the network trained from the start under the kind's guard (``neural.session.train_network``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TypeVar

from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.settings import Settings

Map = TypeVar("Map")  # what a kind's pinn leaves: its map, or its grid and report

WINSLOW = "the start already solves the Winslow equations the network trains on"
QUALITY = "the start is the quality objective's own optimum on these nodes"
TFI_START = "the start, the TFI grid, ranks above the Winslow grid the network trains toward"


def cannot_win(settings: Settings, aux: Sequence[AuxLine] = ()) -> str | None:
    """Why the pinn's network cannot beat its start under ``settings`` with the auxiliary
    lines ``aux``, or None where it may (under the Winslow equations: lines to follow,
    orthogonal sides, a spacing; no warm start: the network is the map) or where Adam epochs
    are asked (a schedule that trains the network whatever it wins).

    The quality objective's start is its optimum on the nodes, with the lines followed: on
    the tuning set's shapes with lines its trained network never ranked better
    (docs/quality_objective.md), so it is not trained there either."""
    if settings.method != "pinn" or settings.warm_start != "elliptic" or settings.adam_epochs:
        return None
    if settings.boundary_mode != "hard" or settings.orthogonal or settings.spacing:
        return None
    if settings.quality_objective:
        return QUALITY
    return None if aux else WINSLOW


def start_or_train(reason: str | None, keep: Callable[[str], Map], train: Callable[[], Map]) -> Map:
    """The one sequence of every kind's pinn, start -> skip -> train -> guard: where its
    network cannot win (``reason``, from :func:`cannot_win` or a kind's own rule, such as
    ``body.untrained.body_cannot_win``), the start kept, ``keep(reason)``, with no network
    built and no torch imported; else ``train()``, which imports the kind's training module
    and trains the network from the start under the kind's guard, the start kept unless a
    trained state is no worse."""
    return keep(reason) if reason else train()


def start_info(start: str, reason: str, guard: dict, seconds: float) -> dict:
    """What the report says of a block whose network is not trained: its ``start``, why
    (``reason``), the ``guard``'s figures and the start's ``seconds``."""
    return {
        "result": "start",
        "start": start,
        "skipped": reason,
        "largest_node_move": 0.0,
        "adam_epochs": 0,
        "lbfgs_iterations": 0,
        "guard": guard,
        "timings": {"start": seconds, "training": 0.0},
    }
