"""What each setting's value must be (scikit-learn's parameter constraints): the rule types,
and the rules of the settings every kind carries."""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass

from pinn_engine.settings.limits import METHODS, OBJECTIVES, PRESETS
from pinn_engine.settings.places import HEXA_PATCH, HEXA_PATCH_NAMES, SIDE_NAMES


@dataclass(frozen=True)
class Options:
    """A setting that takes one of ``values`` (``help``: one line for the routes)."""

    values: tuple
    help: str = ""

    def problem(self, value) -> str | None:
        return None if value in self.values else f"use {', '.join(map(str, self.values))}"


@dataclass(frozen=True)
class Interval:
    """A whole (``kind`` int) or real (``kind`` float) number in ``[low, high]``."""

    kind: type
    low: float
    high: float = math.inf
    help: str = ""

    def problem(self, value) -> str | None:
        whole = isinstance(value, numbers.Integral) and not isinstance(value, bool)
        if self.kind is int and not whole:
            return "must be a whole number"
        if self.kind is float and (
            isinstance(value, bool)
            or not isinstance(value, numbers.Real)
            or not math.isfinite(value)
        ):
            return "must be a finite number"
        if self.low <= value <= self.high:
            return None
        kind = "a whole number" if self.kind is int else "a number"
        show = (lambda x: str(int(x))) if self.kind is int else (lambda x: f"{x:g}")
        if self.high == math.inf:
            return f"must be {kind} >= {show(self.low)}"
        return f"must be {kind} from {show(self.low)} to {show(self.high)}"


@dataclass(frozen=True)
class Pattern:
    """A string matching the regular expression ``regex`` (``hint`` says what it wants)."""

    regex: str
    hint: str
    help: str = ""

    def problem(self, value) -> str | None:
        if isinstance(value, str) and re.fullmatch(self.regex, value):
            return None
        return f"use {self.hint}"


# The shared core's rules (scikit-learn's ``_parameter_constraints``): the method, the preset,
# the network, its training and the elliptic start, which every kind's settings carry. Each
# kind's settings class (``kinds/<kind>/settings.py``) has one table: these, narrowed where
# the kind takes less, and the rules of its own settings. Rules between settings are each
# class's ``check``.
CORE_CONSTRAINTS: dict[str, Options | Interval] = {
    "method": Options(METHODS),
    "preset": Options(PRESETS),
    "boundary_mode": Options(("hard", "penalty")),
    "boundary_fit": Options(("arclength", "tree")),
    "warm_start": Options(("elliptic", "none")),
    "residual": Options(("paper", "scaled"), "Winslow residual: the paper's eq. 13 or scaled"),
    "objective": Options(OBJECTIVES),
    "hidden_layers": Interval(int, 1, 64),
    "neurons": Interval(int, 1, 4096),
    "activation": Options(("tanh", "sin", "sigmoid", "swish"), "hidden layers' activation"),
    "adam_epochs": Interval(int, 0, 1_000_000),
    "learning_rate": Interval(float, 0.0, 1.0, "Adam's learning rate"),
    "lr_decay": Interval(float, 0.0, 1.0, "factor of the learning rate's step decay"),
    "lr_decay_every": Interval(int, 1, help="Adam epochs between learning-rate decays"),
    "batch_size": Interval(int, 1, 1_000_000, "collocation points per Adam epoch"),
    "lbfgs_iterations": Interval(int, 0, 1_000_000),
    "lbfgs_points": Interval(int, 1, 1_000_000, "collocation points of L-BFGS's batch"),
    "lambda2": Interval(float, 0.0),
    "anneal_momentum": Interval(float, 0.0, 1.0, "moving average of lambda1's annealing"),
    "seed": Interval(int, 0, 2**32 - 1),
    "time_limit": Interval(
        float, 0.0, help="seconds of training before the best state so far is kept; 0: none"
    ),
    "dtype": Options(("float32", "float64"), "training precision"),
    "derivatives": Options(("jets", "autograd"), "derivatives: forward jets or autograd"),
    "elliptic_iterations": Interval(int, 0, 1_000_000),
    "lambda_orthogonal": Interval(float, 0.0, help="weight of the orthogonality term"),
    "adapt_strength": Interval(
        float, 0.0, help="with --adapt: the monitor's strength beta; 0: not adapted"
    ),
}


@dataclass(frozen=True)
class Counts:
    """Node counts: a tuple of one of ``lengths`` whole numbers, each at least ``low``."""

    lengths: tuple[int, ...]
    low: int
    help: str = ""

    def problem(self, value) -> str | None:
        whole = isinstance(value, tuple) and all(
            isinstance(n, numbers.Integral) and not isinstance(n, bool) for n in value
        )
        if whole and len(value) in self.lengths and all(n >= self.low for n in value):
            return None
        lengths = " or ".join(map(str, self.lengths))
        return f"must be {lengths} whole numbers of at least {self.low}"


def _patch(name) -> bool:
    """Whether ``name`` is a six-faced domain's patch (imin ... kmax, faceN)."""
    return isinstance(name, str) and bool(HEXA_PATCH.match(name))


@dataclass(frozen=True)
class Places:
    """Places of ``names`` (the sides a 2D kind takes; empty: a six-faced domain's patches
    imin ... kmax, faceN), each at most once; ``spaced``: each paired with its first edge, a
    finite length > 0."""

    spaced: bool
    names: tuple[str, ...] = ()
    help: str = ""

    def problem(self, value) -> str | None:
        items = value if isinstance(value, tuple) else None
        if items is not None and self.spaced:
            pairs = all(isinstance(i, tuple) and len(i) == 2 for i in items)
            items = [n for n, h in items if _positive(h)] if pairs else None
            items = items if items is not None and len(items) == len(value) else None
        known = (lambda n: n in self.names) if self.names else _patch
        if items is not None and all(map(known, items)) and len(set(items)) == len(items):
            return None
        what = "(PLACE, H) pairs, H > 0" if self.spaced else "places"
        places = ", ".join(self.names) if self.names else HEXA_PATCH_NAMES
        return f"must be {what}, each once, of {places}"


def _positive(h) -> bool:
    """Whether ``h`` is a finite real number > 0."""
    real = isinstance(h, numbers.Real) and not isinstance(h, bool)
    return real and math.isfinite(h) and h > 0


# The torch devices a run takes (torch.device's names; auto: cuda where there is one)
DEVICE_NAMES = re.compile(r"^(auto|cpu|mps|cuda(:\d+)?)$")

# The rules of the core's settings that routes give by options of their own shape (node
# counts, side lists, SIDE=H items, a torch device): checked once ``Settings.read`` has read
# them (lists from JSON and saved models made tuples, SIDE=H strings parsed), and not
# iterated by the routes' generic options as the scalar rules are. A 2D kind's node counts and
# places; a six-faced domain's are its own (kinds/hexa/settings.py).
SHAPED_CONSTRAINTS: dict[str, Counts | Places | Pattern] = {
    "lattice": Counts((2,), 2, "nodes of the warm start's lattice"),
    "size": Counts((0, 2), 1, "nodes along i and j; none: the lattice's, or a multi-block's"),
    "spacing": Places(True, SIDE_NAMES, "first-edge length per side"),
    "orthogonal": Places(False, SIDE_NAMES, "sides that grid lines leave at 90 degrees"),
    "device": Pattern(DEVICE_NAMES.pattern[1:-1], "auto, cpu, cuda or cuda:N", "torch device"),
}
