"""The settings every kind's run carries (the shared core), a four-sided domain's."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import ClassVar

from pinn_engine.errors import SettingsError
from pinn_engine.settings.limits import (
    ADAPT_STRENGTH,
    DEFAULT_SIZE,
    HEXA_SIZE,
    MAX_LATTICE_NODES,
    NO_TIME_LIMIT,
)
from pinn_engine.settings.places import parse_sides, parse_spacing
from pinn_engine.settings.rules import CORE_CONSTRAINTS, SHAPED_CONSTRAINTS


@dataclass(frozen=True)
class Settings:
    """The settings every kind's run carries (the shared core): the method, the preset, the
    network, its training and the elliptic start, and the grid's size and the places of its
    spacing and orthogonal lines, which each kind reads and rules its own way. A kind's
    settings class adds its own settings and rules (``kinds/<kind>/settings.py``); this core
    is a four-sided domain's. ``training_key`` is the part that training depends on."""

    # Every field's rule, and the words a refusal of one takes where the kind has its own
    # (``refusal``); the kinds' classes replace them
    CONSTRAINTS: ClassVar[dict] = {**CORE_CONSTRAINTS, **SHAPED_CONSTRAINTS}
    REFUSALS: ClassVar[dict[str, str]] = {}
    # settings a kind takes over every preset (a six-faced domain's shorter L-BFGS run)
    OVER_PRESET: ClassVar[dict] = {}

    method: str = "pinn"
    preset: str = "default"
    # boundary treatment: "hard" (network corrects TFI, exact boundary) or "penalty" (paper)
    boundary_mode: str = "hard"
    boundary_fit: str = "arclength"  # "arclength" or "tree" (paper)
    # "elliptic": start from the converged elliptic grid on ``lattice`` and stop L-BFGS at the
    # last state no worse than it there (starts/warmstart.py); "none": start from TFI (paper)
    warm_start: str = "elliptic"
    lattice: tuple[int, int] = DEFAULT_SIZE  # nodes of the warm start; routes use the output size
    # the grid's nodes along i, j (and k: a six-faced 3D domain); () for a multi-block domain,
    # whose counts come from cell_size
    size: tuple[int, ...] = ()
    residual: str = "scaled"  # Winslow residual: "paper" (eq. 13) or "scaled" (losses.py)
    # pinn: "winslow" (the Winslow equations), "quality" (plus a cell-quality term, and the
    # start and guard keep the best worst angle; kinds.four_sided.problem) or "best" (quality on a
    # four-sided block without spacing or orthogonal sides, winslow elsewhere:
    # ``quality_objective``); other methods: "winslow"
    objective: str = "best"
    hidden_layers: int = 4
    neurons: int = 30
    activation: str = "tanh"
    adam_epochs: int = 0
    learning_rate: float = 1e-3
    lr_decay: float = 0.9
    lr_decay_every: int = 1000
    batch_size: int = 100
    lbfgs_iterations: int = 120
    lbfgs_points: int = 400
    lambda2: float = 30.0
    anneal_momentum: float = 0.9  # moving-average factor of the lambda1 update
    seed: int = 0
    # wall-clock seconds of training, then the best state so far is kept (0: no limit); not
    # in training_key: a stopped training is not cached (cache.py), a complete one is the same
    time_limit: float = NO_TIME_LIMIT
    dtype: str = "float32"  # training precision: float32 (measured: same loss) or float64
    device: str = "auto"
    # derivatives of the map: "jets" (forward-mode, jet/layers.py) or "autograd" (nested
    # torch.autograd.grad, the reference)
    derivatives: str = "jets"
    elliptic_iterations: int = 0  # 0: iterate to convergence; N: the paper's N sweeps from 0
    # SPEC 7: first-edge length per place in user units, e.g. (("bottom", 1e-3),), and the
    # places that grid lines leave at right angles (pinn: loss term, elliptic: control
    # functions); a 2D domain's places are its sides, a six-faced domain's its patches
    spacing: tuple[tuple[str, float], ...] = ()
    orthogonal: tuple[str, ...] = ()
    lambda_orthogonal: float = 300.0  # weight of the orthogonality term (pinn)
    # SPEC 14, a grid adapted to a field (given beside the settings): the monitor's strength
    adapt_strength: float = ADAPT_STRENGTH

    def __post_init__(self) -> None:
        """Each field against its rule, then the rules between fields; nothing is rewritten
        here (``read`` reads a route's or a saved model's values first)."""
        for f in fields(self):
            value = getattr(self, f.name)
            problem = self.CONSTRAINTS[f.name].problem(value)
            if problem:
                raise self.refusal(f.name, value, problem)
        self.check()

    @classmethod
    def refusal(cls, name: str, value, problem: str) -> Exception:
        """The error refusing ``value`` for ``name``: the kind's words where it has them."""
        words = cls.REFUSALS.get(name)
        if words is not None:
            return SettingsError(words.format(value=value))
        return SettingsError(f"{name} {value!r}: {problem}")

    @classmethod
    def read(cls, **values) -> Settings:
        """Settings from a route's or a saved model's values: lists made tuples, places read
        from ``SIDE=H`` strings, dicts or pairs (``read_places``), and a method other than
        the pinn given the Winslow objective (the objective is the pinn's)."""
        for name in ("lattice", "size"):
            if name in values and not isinstance(values[name], str):
                values[name] = tuple(int(n) for n in values[name])
        values.update(cls.read_places(values.get("spacing", ()), values.get("orthogonal", ())))
        if values.get("method", "pinn") != "pinn":
            values["objective"] = "winslow"
        return cls(**values)

    @classmethod
    def read_places(cls, spacing, orthogonal) -> dict:
        """``spacing`` and ``orthogonal`` read as a 2D domain's sides."""
        return {"spacing": parse_spacing(spacing), "orthogonal": parse_sides(orthogonal)}

    @classmethod
    def adopt(cls, settings: Settings) -> Settings:
        """``settings`` as this kind's: the fields they share, this kind's defaults for the
        rest (a route that built the core's settings for a kind's geometry)."""
        if isinstance(settings, cls):
            return settings
        theirs = {f.name for f in fields(settings)}
        return cls(**{f.name: getattr(settings, f.name) for f in fields(cls) if f.name in theirs})

    def check(self) -> None:
        """The rules between a 2D domain's settings: the start's, the places'."""
        self.check_start()
        self.check_places()

    def check_places(self) -> None:
        """Orthogonal sides need a method that turns grid lines, and spacing the converged
        elliptic solver."""
        if self.orthogonal and self.method not in ("pinn", "elliptic"):
            raise SettingsError(
                f"orthogonal sides need the pinn or elliptic method, not {self.method}"
            )
        if (
            self.method == "elliptic"
            and self.elliptic_iterations
            and (self.spacing or self.orthogonal)
        ):
            raise SettingsError(
                "spacing and orthogonal sides need the converged elliptic solver "
                "(elliptic_iterations 0, not the paper's sweeps)"
            )

    def check_start(self) -> None:
        """The elliptic warm start needs the hard boundary (every kind's rule)."""
        if self.warm_start == "elliptic" and self.boundary_mode != "hard":
            raise SettingsError(
                "the elliptic warm start needs the hard boundary mode; with the "
                "penalty boundary set the warm start to none"
            )

    @property
    def topology(self) -> str:
        """A body's grid, o or c (``kinds.body.settings``); none for the other kinds."""
        return "none"

    @property
    def quality_objective(self) -> bool:
        """Whether a four-sided pinn block takes the quality objective (its start, term and
        ranking: starts/quality_start.py; a multi-block run makes ``best`` winslow,
        kinds.blocks.run): asked, or by default (``best``) from the elliptic
        warm start where no spacing or orthogonal side is asked (there the spacing's and the
        orthogonal start's grids, which the quality start does not keep, are the start) and
        the lattice is the grid itself (``MAX_LATTICE_NODES``)."""
        if self.method != "pinn" or self.topology != "none" or len(self.size) == len(HEXA_SIZE):
            return False
        if self.objective == "best":
            return (
                self.warm_start == "elliptic"
                and not (self.spacing or self.orthogonal)
                and math.prod(self.lattice) <= MAX_LATTICE_NODES
            )
        return self.objective == "quality"

    @property
    def wall_spacing(self) -> float | None:
        """The first-layer height off a body's wall (``spacing`` of bottom), or None."""
        return dict(self.spacing).get("bottom")

    def to_dict(self) -> dict:
        return asdict(self)

    def training_key(self) -> tuple:
        """The settings that change the trained network (not the output resolution)."""
        skip = {
            "preset",
            "device",
            "time_limit",
            "cell_size",
            "interfaces",
            "size",
            "adapt_strength",
        } | ({"lattice"} if self.warm_start == "none" and not self.quality_objective else set())
        return tuple((f.name, getattr(self, f.name)) for f in fields(self) if f.name not in skip)
