"""The ParaView panels of the mesh filters, the blockMeshDict reader and the Airfoil source
as data: each property's name, label, default, range, choices, help and the algorithm's
method its values go to, one ``Property`` each, by panel (``PANELS``). The plugin turns each
into its decorators; the labels of options come from ``routes.names``, the ranges, choices
and defaults from the kinds' settings and their tables, so the panel, the command line and
pyvista cannot drift apart.

Nothing here imports ParaView: the visibility hints are ParaView's XML as text.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pinn_engine.routes import airfoil_algorithm, dictionary_algorithm
from pinn_engine.routes.multiblock_algorithm import BLOCKING, INTERFACES
from pinn_engine.routes.names import NAMES
from pinn_engine.settings import (
    ADAPT_STRENGTH,
    BLOCKS_METHOD,
    DEFAULT_SIZE,
    DICTIONARY_METHODS,
    FACE_ANGLE,
    HEXA_METHOD,
    HEXA_METHODS,
    HEXA_SIZE,
    KIND_SETTINGS,
    MAX_SIDE_NODES,
    METHODS,
    MIN_HEXA_NODES,
    MULTIBLOCK_METHODS,
    OBJECTIVES,
    PANEL_TIME_LIMIT,
    PRESETS,
    make_settings,
    option_constraints,
)

_DEFAULTS = KIND_SETTINGS["four_sided"]()
_PAPER = make_settings("pinn", "paper")
TOPOLOGY_ENTRIES = ("Four-sided domain", "O-grid", "C-grid", "Automatic")  # SetTopology's order


def as_given(value):
    """A value as ParaView passes it (the algorithm's method converts it itself; an emptied
    text comes as None)."""
    return value


def _visible(prop: str, values: str, key: str = "values") -> str:
    """Shown only while the property ``prop`` has one of ``values`` (indices)."""
    return (
        '<PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        f'property="{prop}" {key}="{values}"/>'
    )


NEURAL = _visible("Method", "0 1")  # training settings: pinn and mgnet only
FOUR_SIDED = _visible("Topology", "0 3")  # SPEC 7 settings: four-sided (and Automatic)
BODY = _visible("Topology", "1 2 3")  # O- and C-grid settings (and Automatic)
PINN_ONLY = _visible("Method", "0", "value")


def for_preset(preset: int, methods: str) -> str:
    """Shown only under Preset ``preset`` (index) and for the Method indices ``methods``."""
    return (
        '<PropertyWidgetDecorator type="CompositeDecorator"><Expression type="and">'
        + _visible("Method", methods)
        + _visible("Preset", str(preset), "value")
        + "</Expression></PropertyWidgetDecorator>"
    )


def method_is(methods: tuple[str, ...], name: str) -> str:
    """Shown only while Method is ``name`` (of ``methods``, the panel's enumeration)."""
    return _visible("Method", str(methods.index(name)), "value")


def whole_range(name: str) -> dict:
    """The panel range of a whole-number setting, from the kinds' tables
    (settings.option_constraints)."""
    rule = option_constraints()[name]
    return {"min": int(rule.low), "max": int(rule.high)}


@dataclass(frozen=True)
class Property:
    """One property of a filter's panel: ``method`` (the plugin's method; ParaView 5.11 orders
    a Python plugin's properties by it, hence its P-number), ``name`` (ParaView's, which
    scripts set), ``vector`` ("int", "double" or "string"), ``default``, ``doc``, and
    ``call``, the algorithm's method that takes ``before`` then each value by ``convert``.
    ``option``: the option it sets, whose label (``routes.names``) it shows unless ``label``
    gives the panel's own; ``bounds``, ``enum``, ``hint`` (a visibility decorator's XML),
    ``advanced``, ``files`` (a file chooser's extension and description) and ``boolean`` (a
    check box) as ParaView takes them."""

    method: str
    name: str
    vector: str
    default: object
    doc: str
    call: str
    option: str | None = None
    label: str | None = None
    convert: Callable = int
    before: tuple = ()
    bounds: dict | None = None
    enum: tuple | None = None
    hint: str | None = None
    advanced: bool = False
    files: tuple[str, str] | None = None
    boolean: bool = False

    @property
    def shown(self) -> str | None:
        """The label the panel shows (None: ParaView shows the name)."""
        return self.label or (NAMES[self.option].label if self.option in NAMES else None)


def _setting(setting: str, vector: str, **kw) -> Property:
    """A property of ``setting`` given by ``SetPanelSetting``: its default, its label and
    its value's type from the setting's."""
    base = {
        "call": "SetPanelSetting",
        "before": (setting,),
        "option": setting,
        "convert": {"int": int, "double": float}[vector],
        "default": getattr(_DEFAULTS, setting),
    }
    return Property(vector=vector, **{**base, **kw})


def _per_preset(setting: str, vector: str, number: str, **kw) -> tuple[Property, ...]:
    """The two properties of ``setting``, one per preset (default, paper), each shown under
    its own (its label then "Paper ..."); ``number`` orders them, and a pair ``(default's,
    paper's)`` among ``kw`` gives each its own."""
    label = NAMES[setting].label
    name = label.replace(" ", "").replace("-", "")  # Adam Epochs: AdamEpochs
    presets = (("", "default", _DEFAULTS), ("Paper", "paper", _PAPER))
    return tuple(
        Property(
            method=f"P{number}{prefix}{name}",
            name=f"{prefix}{name}",
            vector=vector,
            default=getattr(settings, setting),
            call="SetPresetSetting",
            before=(preset, setting),
            convert={"int": int, "double": float}[vector],
            option=setting,
            label=f"{prefix} {label}" if prefix else None,
            **{k: v[index] if isinstance(v, tuple) else v for k, v in kw.items()},
        )
        for index, (prefix, preset, settings) in enumerate(presets)
    )


def _text(method: str, name: str, doc: str, call: str, option: str) -> Property:
    """A property of ``option`` typed as text (items the algorithm's ``call`` parses),
    empty by default."""
    return Property(method, name, "string", "", doc, call, option=option, convert=as_given)


def _time_limit(method: str, methods: tuple[str, ...]) -> Property:
    """The Time Limit of a filter whose Method enumerates ``methods``: shown for pinn."""
    return Property(
        method,
        "TimeLimit",
        "double",
        PANEL_TIME_LIMIT,
        _TIME_LIMIT_DOC,
        "SetTimeLimit",
        option="time_limit",
        convert=float,
        bounds={"min": 0.0},
        hint=method_is(methods, "pinn"),
    )


def _model(method: str, effect: str) -> Property:
    """The Model of a 2D filter: a family model's file (SPEC 16), whose ``effect`` on the
    filter's grid its help says."""
    return Property(
        method,
        "Model",
        "string",
        "",
        f"A family model (a .pt file made by pinn-mesh fit, docs/family.md): {effect} "
        "Empty: no model.",
        "SetModel",
        option="model",
        convert=lambda path: path or None,
        files=("pt", "pinn-mesh family models"),
    )


_TIME_LIMIT_DOC = (
    "Seconds of training, then the grid of the best state so far is produced with a warning "
    "(0: no limit). ParaView 5.11 handles no event while a filter runs, so its progress "
    "bar's abort cannot stop a training: set this before Apply (or stop it with "
    "pkill -USR1 -x paraview, which also keeps the best grid so far)."
)

# PINN Structured Mesh: a four-sided domain or a body (SPEC 5, 7 and 9)
FOUR_SIDED_PANEL = (
    Property(
        "P01Method",
        "Method",
        "int",
        0,
        "pinn: the paper's PINN (uses the auxiliary lines); mgnet: plain networks, no "
        "auxiliary lines; tfi: transfinite interpolation; elliptic: the classical elliptic "
        "(Winslow) method.",
        "SetMethod",
        enum=METHODS,
    ),
    Property(
        "P02GridSize",
        "GridSize",
        "int",
        list(DEFAULT_SIZE),
        "Nodes along xi and eta. The default PINN starts from the elliptic grid of this size "
        "and trains anew for a new size (seconds); with Preset paper a new size re-evaluates "
        "the trained network.",
        "SetGridSize",
        option="size",
        bounds={"min": 2, "max": MAX_SIDE_NODES},
        convert=as_given,
    ),
    Property(
        "P03Preset",
        "Preset",
        "int",
        0,
        "default: measured defaults (exact boundary, arc-length fit); paper: the paper's "
        "section 4 (penalty boundary term, decision-tree fit, 1000 elliptic sweeps). Adam "
        "Epochs, L-BFGS Iterations and Lambda2 have a field per preset; the panel shows the "
        "chosen preset's.",
        "SetPreset",
        enum=PRESETS,
    ),
    _setting(
        "time_limit",
        "double",
        method="P03TimeLimit",
        name="TimeLimit",
        default=PANEL_TIME_LIMIT,
        bounds={"min": 0.0},
        hint=NEURAL,
        doc="Seconds of training, then the grid of the best state so far is produced with a "
        "warning (0: no limit). ParaView handles no event while a filter runs; "
        "pkill -USR1 -x paraview ends a training early the same way.",
    ),
    *_per_preset(
        "adam_epochs",
        "int",
        "04",
        advanced=True,
        bounds=whole_range("adam_epochs"),
        hint=(for_preset(0, "0 1"), for_preset(1, "0 1")),
        doc=(
            "Adam epochs of training under Preset default.",
            "Adam epochs of training under Preset paper (the paper's 5000).",
        ),
    ),
    *_per_preset(
        "lbfgs_iterations",
        "int",
        "05",
        advanced=True,
        bounds=whole_range("lbfgs_iterations"),
        hint=(for_preset(0, "0 1"), for_preset(1, "0 1")),
        doc=(
            "L-BFGS iterations after Adam under Preset default.",
            "L-BFGS iterations after Adam under Preset paper (the paper's 500).",
        ),
    ),
    _setting(
        "hidden_layers",
        "int",
        method="P06HiddenLayers",
        name="HiddenLayers",
        advanced=True,
        bounds=whole_range("hidden_layers"),
        hint=NEURAL,
        doc="Hidden layers of each sub-network.",
    ),
    _setting(
        "neurons",
        "int",
        method="P07Neurons",
        name="Neurons",
        advanced=True,
        bounds=whole_range("neurons"),
        hint=NEURAL,
        doc="Neurons per hidden layer.",
    ),
    *_per_preset(
        "lambda2",
        "double",
        "08",
        bounds={"min": 0.0, "max": 1000.0},
        hint=(for_preset(0, "0"), for_preset(1, "0")),
        doc=(
            "Weight of the auxiliary-line term of the loss under Preset default.",
            "Weight of the auxiliary-line term under Preset paper (the paper's 10).",
        ),
    ),
    _setting(
        "seed",
        "int",
        method="P09Seed",
        name="Seed",
        advanced=True,
        hint=NEURAL,
        doc="Random seed of training (runs are repeatable).",
    ),
    Property(
        "P10CornerIndices",
        "CornerIndices",
        "int",
        [-1, -1, -1, -1],
        "The four corner point indices of the boundary; -1 -1 -1 -1 finds them "
        "automatically (the four sharpest turns).",
        "SetCorners",
        option="corners",
        convert=as_given,
    ),
    _setting(
        "objective",
        "int",
        method="P11Objective",
        name="Objective",
        default=OBJECTIVES.index(_DEFAULTS.objective),
        convert=lambda index: OBJECTIVES[int(index)],
        enum=OBJECTIVES,
        hint=PINN_ONLY,
        doc="best (default): the grid of lowest worst cell among TFI, the elliptic grid, "
        "their blends and the quality-optimised grid, its mean at most 0.5 degrees above "
        "the elliptic grid's, auxiliary lines followed (winslow under a spacing or "
        "orthogonal sides); winslow: train on the Winslow equations; quality: add a "
        "cell-quality term that lowers the worst cell's largest angle, starting from the "
        "better of the elliptic and TFI grids (pinn only).",
    ),
    Property(
        "P11Topology",
        "Topology",
        "int",
        TOPOLOGY_ENTRIES.index("Automatic"),
        "Automatic (default): an O-grid for a body (the Airfoil source or reader's curve, "
        "one curve that turns sharply at two points at most, or two closed polylines: body "
        "inside far field), else a four-sided domain. Four-sided domain: the input is a "
        "closed boundary with four corners. O-grid / C-grid: the input is a body such as an "
        "airfoil (the Airfoil source, or a .dat file opened with the Airfoil reader): one "
        "curve, meshed out to a far-field circle of Far Field Radius chords, or two closed "
        "polylines (body inside far field). The C-grid's wake cut leaves a sharp trailing "
        "edge, or a blunt base's middle. Methods pinn, tfi, elliptic (docs/airfoils.md).",
        "SetTopology",
        enum=TOPOLOGY_ENTRIES,
    ),
    Property(
        "P12FarFieldRadius",
        "FarFieldRadius",
        "double",
        KIND_SETTINGS["body"]().farfield,
        "Far-field circle radius in chords about mid-chord.",
        "SetFarFieldRadius",
        option="farfield",
        convert=as_given,
        bounds={"min": option_constraints()["farfield"].low},
        hint=BODY,
    ),
    Property(
        "P13WallSpacing",
        "WallSpacing",
        "double",
        0.0,
        "First-layer height off the body wall, in the body's units (0: half the mean node "
        "spacing along the wall).",
        "SetWallSpacing",
        option="spacing",
        label="Wall Spacing",
        convert=as_given,
        bounds={"min": 0.0},
        hint=BODY,
    ),
    Property(
        "P14FirstEdgeSpacing",
        "FirstEdgeSpacing",
        "double",
        [0.0, 0.0, 0.0, 0.0],
        "Length of the first grid edge leaving the bottom, right, top and left sides, in the "
        "boundary's units (0: that side keeps the even distribution). The spacing grows "
        "smoothly away from the side (Vinokur's stretching); pinn, tfi and elliptic, "
        "four-sided domains (docs/boundary_layer.md).",
        "SetSpacing",
        option="spacing",
        convert=float,
        hint=FOUR_SIDED,
    ),
    Property(
        "P15OrthogonalSides",
        "OrthogonalSides",
        "int",
        [0, 0, 0, 0],
        "1 for each of the bottom, right, top and left sides that grid lines are to leave at "
        "90 degrees (pinn: a loss term; elliptic: Hilgenstock control functions; not tfi or "
        "mgnet).",
        "SetOrthogonal",
        option="orthogonal",
        label="Orthogonal Sides",
        bounds={"min": 0, "max": 1},
        hint=FOUR_SIDED,
    ),
    Property(
        "P20PatchNames",
        "PatchNames",
        "string",
        "bottom right top left",
        "Boundary patch names for solver formats (File > Save Data: PLOT3D, CGNS, SU2, Gmsh, "
        "OpenFOAM): four names for the bottom, right, top and left sides, or SIDE=NAME items "
        "such as 'bottom=wall top=wall'. Sides with the same name form one patch.",
        "SetPatchNames",
        option="patches",
        convert=as_given,
    ),
    _model(
        "P21Model",
        "the boundary is meshed as a member of its family, its interior in a forward pass "
        "instead of its own run, and its Grid Size must be the family's.",
    ),
)

# PINN Structured Mesh (Multi-Block): a multi-block 2D domain (SPEC 10 and 13)
BLOCKS_PANEL = (
    Property(
        "P00Blocking",
        "Blocking",
        "int",
        0,
        "Manual: the block edges are the open polylines you give (on Input or Block Edges); "
        "with none given, they are proposed as by Automatic. Automatic: they are proposed "
        "from the boundary and its holes alone (leave Block Edges empty): O-rings round "
        "holes, an edge from each concave corner, junction centres cut round their middle "
        "(docs/blocking.md); the output port Block Edges shows them.",
        "SetBlocking",
        enum=tuple(b.capitalize() for b in BLOCKING),
    ),
    Property(
        "P01Method",
        "Method",
        "int",
        MULTIBLOCK_METHODS.index(BLOCKS_METHOD),
        "pinn (default): each block's network trained on the Winslow equations from the "
        "elliptic grid of all blocks, its sides held, kept where it is no worse (and fitted "
        "to auxiliary lines, if given; Time Limit bounds the training); elliptic: Winslow on "
        "all blocks at once (interface nodes move like interior nodes); tfi: each block's "
        "transfinite interpolation of its side nodes.",
        "SetMethod",
        enum=MULTIBLOCK_METHODS,
    ),
    _time_limit("P01TimeLimit", MULTIBLOCK_METHODS),
    Property(
        "P02CellSize",
        "CellSize",
        "double",
        KIND_SETTINGS["blocks"]().cell_size,
        "Cell length in the boundary's units (0: the domain's diagonal / 40). A chain of "
        "opposite sides through the blocks takes its longest side over the cell size, "
        "rounded up, at least 2 cells.",
        "SetCellSize",
        option="cell_size",
        convert=as_given,
        bounds={"min": option_constraints()["cell_size"].low},
    ),
    Property(
        "P03Interfaces",
        "Interfaces",
        "int",
        INTERFACES.index(KIND_SETTINGS["blocks"]().interfaces),
        "free: interface nodes are solved like interior nodes, so grid lines cross the block "
        "edges smoothly (elliptic); fixed: they stay on the drawn edges.",
        "SetInterfaces",
        enum=INTERFACES,
    ),
    _text(
        "P04PatchNames",
        "PatchNames",
        "Names of boundary pieces (a piece runs between two block corners or junctions), for "
        "solver formats and for First Edge Spacing and Orthogonal Patches: items separated "
        "by spaces, X,Y=NAME[:TYPE] naming the piece nearest (X, Y) (negative coordinates "
        "too), hole1=NAME[:TYPE] or boundary=NAME[:TYPE] every piece of that ring, e.g. "
        "'hole1=cylinder:wall -0.5,0=inlet:inflow'. Pieces with the same name form one "
        "patch; unnamed pieces are boundary, hole1, hole2, ...",
        "SetPatchNames",
        "patches",
    ),
    _text(
        "P05FirstEdgeSpacing",
        "FirstEdgeSpacing",
        "Length of the first grid edge leaving a patch, in the boundary's units: NAME=H items "
        "separated by spaces, e.g. 'cylinder=0.005' (empty: none); X,Y=H items grade the "
        "blocks across the block side nearest (X, Y), interior ones too: the cells on both "
        "sides H across it, growing along the chain by at most 1.25 a cell, e.g. "
        "'0.3,0.2=0.005'. The spacing grows smoothly away from the patch (Vinokur's "
        "stretching); all methods (docs/multiblock.md).",
        "SetSpacing",
        "spacing",
    ),
    _text(
        "P06OrthogonalPatches",
        "OrthogonalPatches",
        "Patches that grid lines leave at 90 degrees: names separated by commas, e.g. "
        "'cylinder' (empty: none); all methods.",
        "SetOrthogonal",
        "orthogonal",
    ),
    _text(
        "P07CellCounts",
        "CellCounts",
        "Cells along chosen chains of block sides: X,Y=N items separated by spaces, each "
        "giving the chain through the block side nearest (X, Y) N cells, e.g. '1.2,0.41=60' "
        "(empty: every chain from Cell Size). Opposite sides of every block share a count.",
        "SetCells",
        "cells",
    ),
    _text(
        "P08Gradings",
        "Gradings",
        "Expansion ratios along chosen chains of block sides, as blockMesh grades: X,Y=R "
        "items separated by spaces, each growing the cells along the chain through the block "
        "side nearest (X, Y) geometrically, the last R times the first (the first at that "
        "side's end nearest the point), e.g. '1.5,-2=4' (empty: none).",
        "SetGradings",
        "grading",
    ),
    _model(
        "P09Model",
        "its members are of this blocking, and its nodes start the blocks' Winslow solve; "
        "the blocks' field data NetworkResult (family where the grid solved from them is "
        "kept, else start) and FamilyModel say what was kept.",
    ),
)

# The Method help of the hexahedral filter, for the methods settings.HEXA_METHODS has
_HEXA_METHOD_DOCS = {
    "tfi": "3D transfinite interpolation of the six face grids",
    "elliptic": "the 3D Winslow equations solved to convergence from the TFI grid",
    "pinn": "a physics-informed network trained on the 3D Winslow equations, the face "
    "grids built in",
}

# PINN Structured Mesh (Hexahedral): a six-faced 3D domain (SPEC 11)
HEXA_PANEL = (
    Property(
        "P01Method",
        "Method",
        "int",
        HEXA_METHODS.index(HEXA_METHOD),
        "; ".join(f"{m}: {_HEXA_METHOD_DOCS[m]}" for m in HEXA_METHODS) + ".",
        "SetMethod",
        enum=HEXA_METHODS,
    ),
    Property(
        "P02GridSize",
        "GridSize",
        "int",
        list(HEXA_SIZE),
        f"Nodes along i, j and k (at least {MIN_HEXA_NODES} each).",
        "SetGridSize",
        option="size",
        convert=as_given,
        bounds={"min": MIN_HEXA_NODES},
    ),
    _time_limit("P02TimeLimit", HEXA_METHODS),
    Property(
        "P03FaceAngle",
        "FaceAngle",
        "double",
        FACE_ANGLE,
        "For a surface without a FaceId cell array (an STL file): its faces are the regions "
        "between edges where neighbouring triangles' normals differ by more than this many "
        "degrees; there must be six. Ignored when the input has FaceId.",
        "SetFaceAngle",
        option="face_angle",
        convert=float,
        bounds={"min": 1.0, "max": 179.0},
    ),
    _text(
        "P03PatchNames",
        "PatchNames",
        "Boundary patch names of the six faces for solver formats (File > Save Data: PLOT3D, "
        "CGNS, SU2, Gmsh, OpenFOAM): six names for imin, imax, jmin, jmax, kmin and kmax, or "
        "SIDE=NAME[:TYPE] items, SIDE one of those or faceN (the input face whose FaceId is "
        "N; Output Messages lists which side each face became), such as "
        "'face2=inlet:inflow kmin=floor:wall' (empty: the faces' own names). Faces with the "
        "same name form one patch.",
        "SetPatchNames",
        "patches",
    ),
    _text(
        "P04FirstEdgeSpacing",
        "FirstEdgeSpacing",
        "Length of the first grid edge leaving a face, in the surface's units: PATCH=H items "
        "separated by spaces, PATCH one of imin, imax, jmin, jmax, kmin, kmax, e.g. "
        "'kmin=0.002' (empty: none). The spacing grows smoothly away from the face; all "
        "methods (docs/hexa.md).",
        "SetSpacing",
        "spacing",
    ),
    _text(
        "P05OrthogonalPatches",
        "OrthogonalPatches",
        "Faces that grid lines leave at 90 degrees: imin, imax, jmin, jmax, kmin or kmax "
        "separated by commas, e.g. 'kmin' (empty: none); elliptic and pinn.",
        "SetOrthogonal",
        "orthogonal",
    ),
)

# The 2D filters' Adapt Strength (SPEC 14), after their other properties; its Field Array
# lists the Field input's arrays (an ArrayListDomain, the plugin's XML)
ADAPT_STRENGTH_PROPERTY = Property(
    "P91AdaptStrength",
    "AdaptStrength",
    "double",
    ADAPT_STRENGTH,
    "With a Field input: the monitor's strength beta, M = sqrt(1 + beta^2 |grad f|^2 / max "
    "|grad f|^2); cells where M is large get smaller. The grid is adapted less where the "
    "worst cell would exceed the unadapted one's by more than 10 degrees, and kept "
    "unadapted where that carries the field no better.",
    "SetAdaptStrength",
    option="adapt_strength",
    convert=float,
    bounds={"min": 0.0, "max": 100.0},
)

# The blockMeshDict reader's panel (SPEC 15): its methods and interfaces the blocks3d kind's
_DICTIONARY = dictionary_algorithm.DEFAULT
DICTIONARY_PANEL = (
    Property(
        "P01Method",
        "Method",
        "int",
        DICTIONARY_METHODS.index(_DICTIONARY.method),
        "pinn: the better of the Winslow grid and blockMesh's placement; elliptic: the 3D "
        "Winslow grid over all blocks; tfi: blockMesh's placement.",
        "SetMethod",
        "method",
        enum=DICTIONARY_METHODS,
    ),
    Property(
        "P02Interfaces",
        "Interfaces",
        "int",
        dictionary_algorithm.INTERFACES.index(_DICTIONARY.interfaces),
        "free: nodes on faces between blocks solved like interior nodes; fixed: blockMesh's "
        "placement of those faces kept.",
        "SetInterfaces",
        "interfaces",
        enum=dictionary_algorithm.INTERFACES,
    ),
)

# The Airfoil source's panel: a NACA section (SPEC 9)
AIRFOIL_PANEL = (
    Property(
        "P01NACA",
        "NACA",
        "string",
        airfoil_algorithm.NACA,
        "Four digits, e.g. 0012 or 2412.",
        "SetNACA",
        "naca",
        convert=as_given,
    ),
    Property(
        "P02SharpTrailingEdge",
        "SharpTrailingEdge",
        "int",
        int(airfoil_algorithm.SHARP),
        "Closed trailing edge (for the C-grid); off: the classical blunt one (O-grid).",
        "SetSharpTrailingEdge",
        boolean=True,
    ),
)

# Each panel: a mesh filter's by the kind(s) it meshes, the reader's and the source's
PANELS = {
    "four-sided": (*FOUR_SIDED_PANEL, ADAPT_STRENGTH_PROPERTY),
    "blocks": (*BLOCKS_PANEL, ADAPT_STRENGTH_PROPERTY),
    "hexa": HEXA_PANEL,
    "dictionary": DICTIONARY_PANEL,
    "airfoil": AIRFOIL_PANEL,
}
