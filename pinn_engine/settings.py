"""Every setting of a meshing run, the paper preset and the measured defaults."""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import asdict, dataclass, fields, replace

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


# Every setting's rule, in one place (scikit-learn's ``_parameter_constraints``): the Settings
# dataclass checks them, and the command line, the VTK filter, the plugin panel and the
# pyvista accessor take their choices and ranges from here. Rules between settings are in
# ``Settings.__post_init__`` and ``make_settings``.
PARAMETER_CONSTRAINTS: dict[str, Options | Interval] = {
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
    "topology": Options(TOPOLOGIES),
    "naca": Pattern(r"(\d{4})?", "a NACA 4-digit code such as 0012"),
    "farfield": Interval(float, 1.0),  # chords: a far field inside the body is no domain
    "cell_size": Interval(
        float, 0.0, help="multi-block: cell size in your units; 0: the diagonal / 40"
    ),
    "interfaces": Options(
        ("free", "fixed"),
        "multi-block: free (interface nodes solved like interior nodes) or fixed (as drawn)",
    ),
    "adapt_strength": Interval(
        float, 0.0, help="with --adapt: the monitor's strength beta; 0: not adapted"
    ),
    "face_angle": Interval(
        float,
        0.0,
        180.0,
        "six-faced surface without FaceId (an STL): faces end where neighbouring triangles' "
        "normals differ by more than this many degrees",
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


def _place(name) -> bool:
    """Whether ``name`` is a side (bottom ... left) or a six-faced domain's patch."""
    return isinstance(name, str) and (name in SIDE_NAMES or bool(HEXA_PATCH.match(name)))


@dataclass(frozen=True)
class Places:
    """Sides (bottom ... left) or a six-faced domain's patches (imin ... kmax, faceN), each
    at most once; ``spaced``: each paired with its first edge, a finite length > 0."""

    spaced: bool
    help: str = ""

    def problem(self, value) -> str | None:
        items = value if isinstance(value, tuple) else None
        if items is not None and self.spaced:
            pairs = all(isinstance(i, tuple) and len(i) == 2 for i in items)
            items = [n for n, h in items if _positive(h)] if pairs else None
            items = items if items is not None and len(items) == len(value) else None
        if items is not None and all(map(_place, items)) and len(set(items)) == len(items):
            return None
        what = "(SIDE, H) pairs, H > 0" if self.spaced else "sides"
        return f"must be {what}, each side once: {', '.join(SIDE_NAMES)} or {HEXA_PATCH_NAMES}"


def _positive(h) -> bool:
    """Whether ``h`` is a finite real number > 0."""
    real = isinstance(h, numbers.Real) and not isinstance(h, bool)
    return real and math.isfinite(h) and h > 0


# The torch devices a run takes (torch.device's names; auto: cuda where there is one)
DEVICE_NAMES = re.compile(r"^(auto|cpu|mps|cuda(:\d+)?)$")

# The rules of the settings each route gives by options of their own shape (node counts, side
# lists, SIDE=H items, a torch device): checked once Settings has read them (lists from JSON
# and saved models made tuples, SIDE=H strings parsed), and not iterated by the routes' generic
# options as PARAMETER_CONSTRAINTS is. With it every field of Settings has one rule.
SHAPED_CONSTRAINTS: dict[str, Counts | Places | Pattern] = {
    "lattice": Counts((2,), 2, "nodes of the warm start's lattice"),
    "size": Counts((0, 2, 3), 1, "nodes along i, j (and k); none for a multi-block domain"),
    "spacing": Places(True, "first-edge length per side or patch"),
    "orthogonal": Places(False, "sides or patches that grid lines leave at 90 degrees"),
    "device": Pattern(DEVICE_NAMES.pattern[1:-1], "auto, cpu, cuda or cuda:N", "torch device"),
}


def setting_problem(name: str, value) -> str | None:
    """What is wrong with ``value`` for the setting ``name`` (None: nothing); each route
    prefixes its own name for the setting."""
    rule = PARAMETER_CONSTRAINTS.get(name)
    return rule.problem(value) if rule is not None else None


@dataclass(frozen=True)
class Settings:
    """Every setting of a run; ``training_key`` is the part that training depends on."""

    method: str = "pinn"
    preset: str = "default"
    # boundary treatment: "hard" (network corrects TFI, exact boundary) or "penalty" (paper)
    boundary_mode: str = "hard"
    boundary_fit: str = "arclength"  # "arclength" or "tree" (paper)
    # "elliptic": start from the converged elliptic grid on ``lattice`` and stop L-BFGS at the
    # last state no worse than it there (starts/warmstart.py); "none": start from TFI (paper)
    warm_start: str = "elliptic"
    lattice: tuple[int, int] = (41, 21)  # nodes of the warm start; routes use the output size
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
    # SPEC 7: first-edge length per side in user units, e.g. (("bottom", 1e-3),), and the
    # sides that grid lines leave at right angles (pinn: loss term, elliptic: control functions)
    spacing: tuple[tuple[str, float], ...] = ()
    orthogonal: tuple[str, ...] = ()
    lambda_orthogonal: float = 300.0  # weight of the orthogonality term (pinn)
    # SPEC 9, a body instead of a four-sided domain: "o" or "c" ("none": four-sided), a NACA
    # 4-digit section instead of a body file ("": none), the far-field circle's radius in
    # chords about mid-chord (a body given with its own far-field curve ignores it); the
    # first-layer height off the wall is ``spacing`` of the side "bottom"
    topology: str = "none"
    naca: str = ""
    farfield: float = 15.0
    # SPEC 10, a multi-block domain (block edges given): the cells' length in user units
    # (0: the domain's diagonal / 40), and whether interface nodes are solved ("free") or
    # stay on the drawn edges ("fixed")
    cell_size: float = 0.0
    interfaces: str = "free"
    # SPEC 14, a grid adapted to a field (given beside the settings): the monitor's strength
    adapt_strength: float = ADAPT_STRENGTH
    # SPEC 11, a six-faced 3D domain (three sizes): a surface without FaceId is split into
    # faces where it bends by more than this many degrees; spacing and orthogonal then name
    # the patches imin ... kmax
    face_angle: float = FACE_ANGLE

    def __post_init__(self) -> None:
        for name in PARAMETER_CONSTRAINTS:
            problem = setting_problem(name, getattr(self, name))
            if problem:
                raise SettingsError(f"{name} {getattr(self, name)!r}: {problem}")
        self._read()
        for name, rule in SHAPED_CONSTRAINTS.items():
            problem = rule.problem(getattr(self, name))
            if problem:
                raise SettingsError(f"{name} {getattr(self, name)!r}: {problem}")

    def _read(self) -> None:
        """The rules between settings, with the shaped settings read (lists made tuples,
        SIDE=H strings parsed) in their kind's terms: a six-faced domain's (three sizes) or
        a 2D domain's."""
        if self.method != "pinn":  # the objective is the pinn's (make_settings says so)
            object.__setattr__(self, "objective", "winslow")
        if self.warm_start == "elliptic" and self.boundary_mode != "hard":
            raise SettingsError(
                "the elliptic warm start needs the hard boundary mode; with the "
                "penalty boundary set the warm start to none"
            )
        lattice = tuple(int(n) for n in self.lattice)
        if len(lattice) != 2 or min(lattice) < 2:
            raise SettingsError(
                f"lattice must be two node counts of at least 2, got {self.lattice}"
            )
        object.__setattr__(self, "lattice", lattice)  # lists (JSON, saved models) -> tuple
        object.__setattr__(self, "size", tuple(int(n) for n in self.size))
        if len(self.size) == len(HEXA_SIZE):
            self._check_hexa()
            return
        object.__setattr__(self, "spacing", parse_spacing(self.spacing))
        object.__setattr__(self, "orthogonal", parse_sides(self.orthogonal))
        if self.topology != "none":
            self._check_body()
        elif self.naca:
            raise SettingsError(f"naca {self.naca}: a NACA section needs topology o or c")
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

    def _check_hexa(self) -> None:
        """The rules of six-faced 3D domains (SPEC 11): their methods, spacing and
        orthogonality on the patches imin ... kmax (in the route's words)."""
        if self.method not in HEXA_METHODS:
            raise InputError(
                f"{{method:{self.method}}}: six-faced 3D domains are meshed by "
                f"{', '.join(HEXA_METHODS)}"
            )
        spacing = parse_patch_spacing(self.spacing)
        orthogonal = parse_patch_walls(self.orthogonal)
        object.__setattr__(self, "spacing", spacing)
        object.__setattr__(self, "orthogonal", orthogonal)
        if orthogonal and self.method == "tfi":
            raise InputError(
                f"{{orthogonal}} {','.join(orthogonal)}: use {{method:elliptic}} or pinn (tfi's "
                "grid lines cannot turn to a patch's normal)"
            )
        for axis, name in enumerate("ijk"):
            if {f"{name}min", f"{name}max"} <= set(orthogonal) and self.size[axis] < OPPOSITE_NODES:
                raise InputError(
                    f"{{orthogonal}} {name}min,{name}max: give at least {OPPOSITE_NODES} nodes "
                    f"along {name} ({{size}}), one first layer for each"
                )

    def _check_body(self) -> None:
        """The rules of O- and C-grids (SPEC 9): their methods, and the wall as the one side
        that spacing and orthogonality apply to."""
        if self.method not in BODY_METHODS:
            raise SettingsError(
                f"method {self.method}: O- and C-grids are made by "
                f"{', '.join(BODY_METHODS)} ({self.method} meshes four-sided domains only)"
            )
        if self.objective == "quality":
            raise SettingsError("objective quality: for four-sided domains, not O- and C-grids")
        if any(side != "bottom" for side, _ in self.spacing):
            raise SettingsError(
                "spacing: an O- or C-grid takes bottom=H (the first layer off the wall)"
            )
        if any(side != "bottom" for side in self.orthogonal):
            raise SettingsError("orthogonal: an O- or C-grid takes bottom (the body wall)")
        if self.orthogonal and self.method == "tfi":
            raise SettingsError(
                "orthogonal bottom: tfi's straight columns cannot leave the wall at right "
                "angles; use method elliptic or pinn"
            )

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


def make_settings(method: str = "pinn", preset: str = "default", **overrides) -> Settings:
    """Settings for ``method`` under ``preset``, then ``overrides`` (None values ignored).

    The elliptic warm start needs the hard boundary: asking for the penalty boundary without
    naming a warm start turns it off, and a run without warm start gets the schedule and
    losses of ``FROM_TFI`` unless they are given. A six-faced domain (three sizes) trains
    ``HEXA_LBFGS_ITERATIONS`` unless told otherwise.
    """
    base = Settings(method=method, preset=preset)
    if preset == "paper":
        base = replace(base, **PAPER)
    given = {k: v for k, v in overrides.items() if v is not None}
    for name in given:
        if name not in Settings.__dataclass_fields__:
            raise unknown_name(name, Settings.__dataclass_fields__, "setting")
    if given.get("objective") == "quality" and method != "pinn":
        raise SettingsError(f"objective quality is for the pinn method, not {method}")
    if given.get("boundary_mode") == "penalty" and "warm_start" not in given:
        given["warm_start"] = "none"
    if given.get("warm_start") == "none" and preset == "default":
        given = {**FROM_TFI, **given}
    if len(given.get("size", ())) == len(HEXA_SIZE):
        given = {"lbfgs_iterations": HEXA_LBFGS_ITERATIONS, **given}
    return replace(base, **given)
