"""Every setting of a meshing run, the paper preset and the measured defaults."""

from __future__ import annotations

import functools
import math
import numbers
import re
from dataclasses import asdict, dataclass, fields
from typing import ClassVar

from pinn_engine.errors import InputError, SettingsError, unknown_name
from pinn_engine.patchnames import FACE_PREFIX

METHODS = ("pinn", "mgnet", "tfi", "elliptic")
NEURAL = ("pinn", "mgnet")  # the methods that train a network
PRESETS = ("default", "paper")
# SPEC 7, --objective (pinn): best (the default: the quality objective's grid where it applies,
# the Winslow equations' elsewhere), winslow, quality
OBJECTIVES = ("best", "winslow", "quality")
TOPOLOGIES = ("none", "o", "c")  # SPEC 9: a four-sided domain, an O-grid or a C-grid
BODY_METHODS = ("pinn", "tfi", "elliptic")  # the methods of O- and C-grids
MULTIBLOCK_METHODS = ("tfi", "elliptic", "pinn")  # SPEC 10's methods in this build
BLOCKS_METHOD = "pinn"  # multi-block's default method (SPEC 10), on every route
AUTO_BLOCKS = "auto"  # block edges named so are proposed from the boundary (SPEC 13)
HEXA_METHODS = ("pinn", "tfi", "elliptic")  # SPEC 11's methods, in the filter's order
DICTIONARY_METHODS = ("pinn", "elliptic", "tfi")  # SPEC 15's methods, the default first
HEXA_METHOD = "pinn"  # SPEC 11's default (kinds/hexa/problem.py; docs/hexa.md has its figures)
BOX_SIDES = ("imin", "imax", "jmin", "jmax", "kmin", "kmax")  # a six-faced domain's patches
FACE_ANGLE = 40.0  # degrees between neighbouring triangles' normals that end a face (SPEC 11)
OPPOSITE_NODES = 4  # two orthogonal opposite patches each need a first layer of their own
# A six-faced domain's L-BFGS iterations: its residual falls from the Winslow start by a
# quarter in 20 and a third in 120 at nearly the same grid (docs/hexa.md), each costing
# about 40 ms at 21^3
HEXA_LBFGS_ITERATIONS = 20
# Grid sizes accepted on every route (command line, filter and panel, pyvista, Mesher)
MAX_SIDE_NODES = 20_000
MAX_NODES = 4_000_000  # about 1.5 GB of memory while meshing and writing
# The warm start's elliptic solve grows faster than linearly with the nodes (measured on the
# V notch, 2 busy cores: 1 s at 161 x 81, 16 s at 321 x 161, 106 s at 641 x 321); above this
# many nodes it runs on a coarser lattice of the same shape, and the network is evaluated finer
# (starts/warmstart.py). The default takes the quality objective only up to it: the spline of
# an optimised coarser lattice can fold cells of the finer grid (a bump at 641 x 321: 54).
MAX_LATTICE_NODES = 161 * 81
DEFAULT_SIZE = (41, 21)  # nodes along xi and eta of a four-sided grid or a body (SPEC 5)
HEXA_SIZE = (21, 21, 21)  # SPEC 11's default nodes along i, j and k
MIN_HEXA_NODES = 3  # fewer nodes along a direction leave no interior to solve for
# Training's wall-clock limit in seconds, after which the best state so far is kept
NO_TIME_LIMIT = 0.0  # command line, pyvista, VTK: a limit would tie the grid to machine speed
# SPEC 14's monitor strength beta with --adapt (docs/adaptation.md: the analytic fields'
# interpolation error on the tuning shapes, benchmarks/adapt.py)
ADAPT_STRENGTH = 20.0
PANEL_TIME_LIMIT = 60.0  # ParaView 5.11 freezes while a filter runs; the paper preset (~33 s) fits


def grid_size_problem(ni: int, nj: int) -> str | None:
    """What is wrong with a grid of ``ni`` x ``nj`` nodes, or None; each route prefixes its
    own name for the size (``--size``, ``size=``, Grid Size)."""
    if min(ni, nj) < 2 or max(ni, nj) > MAX_SIDE_NODES or ni * nj > MAX_NODES:
        return (
            f"each side must have 2 to {MAX_SIDE_NODES:,} nodes and the grid at most "
            f"{MAX_NODES:,} nodes"
        )
    return None


def size_problem(size: tuple[int, ...]) -> str | None:
    """What is wrong with a grid size of two node counts (a 2D domain) or more (a six-faced
    3D domain's, :func:`hexa_size_problem`), or None; each route prefixes its own name."""
    return grid_size_problem(*size) if len(size) == 2 else hexa_size_problem(size)


def hexa_size_problem(size: tuple[int, ...]) -> str | None:
    """What is wrong with a six-faced 3D domain's grid size, or None."""
    if len(size) != len(HEXA_SIZE):
        return "a six-faced surface takes three sizes (nodes along i, j and k)"
    if min(size) < MIN_HEXA_NODES:
        return f"each needs at least {MIN_HEXA_NODES} nodes"
    return None


SIDE_NAMES = ("bottom", "right", "top", "left")


def parse_sides(value) -> tuple[str, ...]:
    """Sides from "bottom,left", a list of names or None, in SIDE_NAMES order, checked."""
    if value is None or value == "":
        return ()
    names = value.split(",") if isinstance(value, str) else list(value)
    names = [str(n).strip().lower() for n in names if str(n).strip()]
    bad = [n for n in names if n not in SIDE_NAMES]
    if bad:
        raise SettingsError(f"unknown side {bad[0]!r}; use {', '.join(SIDE_NAMES)}")
    return tuple(s for s in SIDE_NAMES if s in names)


def parse_spacing(value) -> tuple[tuple[str, float], ...]:
    """First-edge spacings from a dict {side: H}, pairs, "side=H" strings (one or a list, or
    "bottom=1e-3,top=0.01"), checked: H a finite positive number, each side at most once."""
    if value is None or value == "" or (hasattr(value, "__len__") and len(value) == 0):
        return ()
    if isinstance(value, dict):
        items = list(value.items())
    else:
        parts = value.split(",") if isinstance(value, str) else list(value)
        items = []
        for part in parts:
            if isinstance(part, str):
                side, sep, h = part.partition("=")
                if not sep:
                    raise SettingsError(f"spacing {part!r}: write SIDE=H, e.g. bottom=0.001")
                items.append((side, h))
            else:
                side, h = part
                items.append((side, h))
    out = {}
    for side, h in items:
        side = str(side).strip().lower()
        if side not in SIDE_NAMES:
            raise SettingsError(f"spacing: unknown side {side!r}; use {', '.join(SIDE_NAMES)}")
        if side in out:
            raise SettingsError(f"spacing: side {side} given twice")
        try:
            h = float(h)
        except (TypeError, ValueError):
            raise SettingsError(f"spacing {side}={h!r}: H must be a number") from None
        if not (0 < h < float("inf")):
            raise SettingsError(f"spacing {side}={h}: H must be a finite length > 0")
        out[side] = h
    return tuple((s, out[s]) for s in SIDE_NAMES if s in out)


# a six-faced domain's patch as --spacing and --orthogonal name it: a side, or faceN (the
# input face whose FaceId is N, resolved to its side once the surface is read)
HEXA_PATCH = re.compile(rf"^({'|'.join(BOX_SIDES)}|{FACE_PREFIX}[0-9]+)$")
HEXA_PATCH_NAMES = ", ".join(BOX_SIDES) + " or faceN"


def parse_patch_spacing(items) -> tuple[tuple[str, float], ...]:
    """A six-faced domain's ``PATCH=H`` items (or (PATCH, H) pairs), checked, in the route's
    words: the first edge H > 0 leaving each patch imin ... kmax (or faceN) given."""
    names = HEXA_PATCH_NAMES
    out: dict[str, float] = {}
    for part in items.items() if hasattr(items, "items") else items or ():
        item = part if isinstance(part, str) else f"{part[0]}={part[1]}"
        name, sep, value = item.partition("=")
        name = name.strip().lower()
        try:
            h = float(value)
        except ValueError:
            h = math.nan
        if not sep or not HEXA_PATCH.match(name) or not (math.isfinite(h) and h > 0):
            raise InputError(f"{{spacing}} {item}: write PATCH=H with H > 0, PATCH one of {names}")
        if out.setdefault(name, h) != h:
            raise InputError(f"{{spacing}} {item}: patch {name} is given two spacings")
    return tuple(out.items())


def parse_patch_walls(items) -> tuple[str, ...]:
    """A six-faced domain's orthogonal patches from ``PATCH[,PATCH...]`` items (imin ...
    kmax or faceN), checked."""
    names = HEXA_PATCH_NAMES
    walls = []
    for item in ([items] if items else []) if isinstance(items, str) else items or ():
        for name in item.split(","):
            name = name.strip().lower()
            if not HEXA_PATCH.match(name):
                raise InputError(f"{{orthogonal}} {item}: unknown patch {name!r}; use {names}")
            walls.append(name)
    return tuple(dict.fromkeys(walls))


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


# Each kind's settings class by its name (``register``): its package registers it on import,
# as meshio's formats register their readers, so that ``make_settings`` and ``read_settings``
# find the class of the kind their values describe
KIND_SETTINGS: dict[str, type[Settings]] = {}


def register(kind: str):
    """A class decorator: ``cls`` is the settings class of ``kind``."""

    def add(cls: type[Settings]) -> type[Settings]:
        KIND_SETTINGS[kind] = cls
        return cls

    return add


def settings_kind(values: dict) -> str:
    """The kind whose settings ``values`` describe, where a route or a saved model did not
    name it: three sizes a six-faced domain, a topology o or c a body, a cell size or
    interfaces a multi-block domain, else a four-sided domain."""
    if len(values.get("size") or ()) == len(HEXA_SIZE) or "face_angle" in values:
        return "hexa"
    if values.get("topology", "none") != "none":
        return "body"
    if "cell_size" in values or "interfaces" in values:
        return "blocks"
    return "four_sided"


@functools.cache
def option_constraints() -> dict[str, Options | Interval | Pattern]:
    """The rules of the settings the routes take as generic options (the command line's
    flags, the VTK algorithms' ``SetSetting``): the core's, then each kind's own scalar
    settings' from its table; a route's topology none is the four-sided domain."""
    rules = dict(CORE_CONSTRAINTS)
    for cls in KIND_SETTINGS.values():
        for name, rule in cls.CONSTRAINTS.items():
            if name not in CORE_CONSTRAINTS and name not in SHAPED_CONSTRAINTS:
                rules.setdefault(name, rule)
    return {**rules, "topology": Options(TOPOLOGIES)}


def setting_problem(name: str, value) -> str | None:
    """What is wrong with ``value`` for the setting ``name`` (None: nothing); each route
    prefixes its own name for the setting."""
    rule = option_constraints().get(name)
    return rule.problem(value) if rule is not None else None


def setting_names() -> frozenset[str]:
    """Every kind's settings' names."""
    return frozenset(f.name for cls in KIND_SETTINGS.values() for f in fields(cls))


def _kind_values(cls: type[Settings], values: dict) -> dict:
    """``values`` less the settings ``cls`` does not carry, where they say no more than that
    (a topology none, no NACA code); another kind's setting refused in one line."""
    own = {f.name for f in fields(cls)}
    out = {}
    for name, value in values.items():
        if name in own:
            out[name] = value
        elif name == "naca" and value:
            raise SettingsError(f"naca {value}: a NACA section needs topology o or c")
        elif (name, value) not in (("topology", "none"), ("naca", "")):
            kinds = [k for k, c in KIND_SETTINGS.items() if name in c.__dataclass_fields__]
            if not kinds:
                raise unknown_name(name, setting_names(), "setting")
            raise SettingsError(f"{name}: a setting of {' and '.join(kinds)} domains, not this one")
    return out


def read_settings(values: dict, kind: str | None = None) -> Settings:
    """The settings a saved model or report holds (``Settings.to_dict``), as the class of
    ``kind`` (or the kind they describe); other kinds' settings, which a file of an older
    build holds at their defaults, are dropped, and a name no kind has is refused."""
    shape = {name: values[name] for name in ("size", "topology") if name in values}
    cls = KIND_SETTINGS[kind or settings_kind(shape)]
    own, known = {f.name for f in fields(cls)}, setting_names()
    unknown = sorted(values.keys() - known)
    if unknown:
        raise unknown_name(unknown[0], sorted(known), "setting")
    return cls.read(**{k: v for k, v in values.items() if k in own})


PAPER = {
    "boundary_mode": "penalty",
    "boundary_fit": "tree",
    "warm_start": "none",
    "residual": "paper",
    "hidden_layers": 4,
    "neurons": 30,
    "activation": "tanh",
    "adam_epochs": 5000,
    "learning_rate": 1e-3,
    "lr_decay": 0.9,
    "lr_decay_every": 1000,
    "batch_size": 100,
    "lbfgs_iterations": 500,
    "lbfgs_points": 1000,
    "lambda2": 10.0,
    "elliptic_iterations": 1000,
    "objective": "winslow",
}


# Training from TFI (no warm start) takes the paper's schedule and losses.
FROM_TFI = {
    "adam_epochs": 5000,
    "lbfgs_iterations": 500,
    "lbfgs_points": 1000,
    "lambda2": 10.0,
    "residual": "paper",
    "objective": "winslow",
}


def make_settings(
    method: str = "pinn", preset: str = "default", kind: str | None = None, **overrides
) -> Settings:
    """Settings of ``kind`` (``KIND_SETTINGS``; None: the kind ``overrides`` describe,
    ``settings_kind``) for ``method`` under ``preset``, then ``overrides`` (None values
    ignored).

    The elliptic warm start needs the hard boundary: asking for the penalty boundary without
    naming a warm start turns it off, and a run without warm start gets the schedule and
    losses of ``FROM_TFI`` unless they are given. A kind's ``OVER_PRESET`` settings (a
    six-faced domain's L-BFGS iterations) apply unless told otherwise.
    """
    given = {k: v for k, v in overrides.items() if v is not None}
    cls = KIND_SETTINGS[kind or settings_kind(given)]
    given = _kind_values(cls, given)
    if given.get("objective") == "quality" and method != "pinn":
        raise SettingsError(f"objective quality is for the pinn method, not {method}")
    if given.get("boundary_mode") == "penalty" and "warm_start" not in given:
        given["warm_start"] = "none"
    if given.get("warm_start") == "none" and preset == "default":
        given = {**FROM_TFI, **given}
    base = cls.read(method=method, preset=preset)
    values = {**asdict(base), **(PAPER if preset == "paper" else {})}
    return cls.read(**{**values, **cls.OVER_PRESET, **given})
