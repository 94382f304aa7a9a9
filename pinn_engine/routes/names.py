"""Each option's name on every route, in one table: the command line's flag, pyvista's
keyword and the ParaView panel's label of every option (a setting of ``settings.Settings`` or
an input a route takes), and the words each route gives a fix in.

An option's one name is its setting's (``adam_epochs``): pyvista's keyword, and on the
command line ``--adam-epochs``. Where SPEC 5 gives the command line a shorter flag
(``--epochs``), that flag is the one the command line shows and names in its messages, and
the one name still works beside it (:func:`cli_aliases`). Which options a domain kind takes
is the kind's own declaration (``job.OPTIONS``); this table only words them.

Importing this module gives ``errors.ROUTE_WORDS`` the routes' words (``pinn_engine``'s
``__init__`` does, so an error raised anywhere reads in them).
"""

from __future__ import annotations

from dataclasses import dataclass

from pinn_engine.errors import register_route_words

ROUTES = ("cli", "pyvista", "paraview")


@dataclass(frozen=True)
class Name:
    """One option's names: ``flag`` (the command line's, SPEC 5), ``keyword`` (pyvista's),
    ``label`` (the ParaView panel's) and ``dest`` (the command line's parsed attribute)."""

    flag: str
    keyword: str
    label: str
    dest: str

    def on(self, route: str) -> str:
        """The name as ``route`` shows it: ``--flag``, ``keyword=`` or the label."""
        return {"cli": self.flag, "pyvista": f"{self.keyword}=", "paraview": self.label}[route]


def _name(option: str, label: str, flag: str | None = None, dest: str | None = None) -> Name:
    """``option``'s names: the flag ``--option-with-dashes`` and the keyword ``option``
    unless SPEC 5 gives another flag (and the parser another ``dest``)."""
    return Name(flag or "--" + option.replace("_", "-"), option, label, dest or option)


# Every option that a route names by itself or in a message, by its one name (a setting's
# name, or the input's pyvista keyword); the flags and labels that differ from it are SPEC 5's
# and the panel's
NAMES: dict[str, Name] = {
    name.keyword: name
    for name in (
        _name("aux", "Auxiliary Lines"),
        _name("blocks", "Block Edges"),
        _name("size", "Grid Size"),
        _name("method", "Method"),
        _name("corners", "Corner Indices"),
        _name("patches", "Patch Names", flag="--patch", dest="patch"),
        _name("spacing", "First Edge Spacing"),
        _name("orthogonal", "Orthogonal Patches"),
        _name("cells", "Cell Counts"),
        _name("grading", "Gradings"),
        _name("cell_size", "Cell Size"),
        _name("interfaces", "Interfaces"),
        _name("save_blocks", "Save Blocks"),
        _name("topology", "Topology"),
        _name("naca", "NACA"),
        _name("farfield", "Far Field Radius"),
        _name("face_angle", "Face Angle"),
        _name("preset", "Preset"),
        _name("objective", "Objective"),
        _name("adam_epochs", "Adam Epochs", flag="--epochs"),
        _name("lbfgs_iterations", "L-BFGS Iterations", flag="--lbfgs"),
        _name("hidden_layers", "Hidden Layers", flag="--layers"),
        _name("neurons", "Neurons"),
        _name("lambda2", "Lambda2"),
        _name("seed", "Seed"),
        _name("time_limit", "Time Limit"),
        _name("elliptic_iterations", "Elliptic Iterations"),
        _name("adapt", "Field"),
        _name("adapt_strength", "Adapt Strength"),
        _name("extrude", "Extrude Thickness"),
        _name("model", "Model"),
        _name("save_model", "Save Model"),
        _name("load_model", "Load Model"),
    )
}


def option_name(option: str, route: str) -> str:
    """``option`` as ``route`` names it (``--epochs``, ``adam_epochs=``, Adam Epochs)."""
    name = NAMES.get(option) or _name(option, option.replace("_", " ").title())
    return name.on(route)


def cli_aliases(option: str) -> tuple[str, ...]:
    """The command line's flags of ``option``: SPEC 5's first, then its one name where that
    differs (``--epochs``, ``--adam-epochs``)."""
    name = NAMES.get(option)
    one = "--" + option.replace("_", "-")
    return (one,) if name is None or name.flag == one else (name.flag, one)


def cli_option(dest: str) -> str:
    """The one name of the option the command line parses into ``dest`` (``patch``:
    ``patches``)."""
    return next((k for k, n in NAMES.items() if n.dest == dest), dest)


# The fixes worded for each route: a template whose ``{option}`` fields are that option's
# name on the route (``NAMES``); ``{{}}`` stays a slot for the token's argument
# (``{method:elliptic}``)
PHRASES = {
    "corners": ("{corners}", "{corners}", "{corners}"),
    "close": (
        "close it (repeat its first point at its end)",
        "close it (a closed line cell, or repeat its first point at its end)",
        "tick Closed in the Poly Line Source's properties (or close the polyline)",
    ),
    "method": ("{method} {{}}", '{method}"{{}}"', "{method} {{}}"),
    "lbfgs": (
        "more {lbfgs_iterations} iterations",
        "a larger {lbfgs_iterations}",
        "more {lbfgs_iterations}",
    ),
    "seed": ("another {seed}",) * 3,
    "converge": (
        "{elliptic_iterations} 0 (solve to convergence)",
        "{elliptic_iterations}0 (solve to convergence)",
        "{preset} default (solves to convergence)",
    ),
    "refuse": ("; --fail-on-folded refuses such grids", "", ""),
    "size": ("{size}",) * 3,
    "cell_size": ("{cell_size}",) * 3,
    "patch": (
        "{patches} SIDE=NAME",
        '{patches}{{"bottom": "wall", ...}}',
        "{patches} (bottom right top left, or SIDE=NAME)",
    ),
    "extrude": ("{extrude} T", "{extrude}", "{extrude}"),
    "output": (
        "-o with .vts, .vtk, .xyz, .cgns, .su2 or .msh, or --format openfoam -o DIR",
        'a path ending in .vts, .vtk, .xyz, .cgns, .su2 or .msh, or format="openfoam"',
        "File > Save Data with a PINN Mesh file type",
    ),
    "h5py": (
        "pip install 'pinn-mesh[cgns]'",
        "pip install 'pinn-mesh[cgns]'",
        "ParaView's HDF5 clashes with pip's h5py, so the writer runs the checkout's .venv "
        "Python: make it with bash scripts/setup.sh (or set PINN_MESH_PYTHON to a Python "
        "with h5py)",
    ),
    "naca": ("{naca} DDDD", '{naca}"DDDD"', "the Airfoil source's {naca} field"),
    "farfield": ("{farfield} R", "{farfield}R", "{farfield}"),
    "topology": ("{topology} o", '{topology}"o"', "{topology} O-grid"),
    "topologies": ("{topology} o or c", '{topology}"o" or "c"', "{topology} O-grid or C-grid"),
    "time_limit": ("a larger {time_limit} (0: none)",) * 3,
    "blocks": (
        "give them with {blocks} EDGES",
        "give them as {blocks}",
        "select their source together with the boundary's (or connect it to {blocks})",
    ),
    "with_blocks": ("with {blocks}, ", "", ""),
    "pieces": (
        "{patches} X,Y=NAME",
        '{patches}["X,Y=NAME", ...]',
        "{patches}' X,Y=NAME items",
    ),
    "face_angle": (
        "a .vtp whose FaceId cell array tags the six faces",
        "another {face_angle} or a FaceId cell array",
        "another {face_angle} or a FaceId cell array",
    ),
    "face_patch": (
        "{patches} SIDE=NAME or faceN=NAME",
        '{patches}{{"imin": "inlet", "face3": "wall", ...}}',
        "{patches} (imin imax jmin jmax kmin kmax, or SIDE=NAME or faceN=NAME)",
    ),
    "spacing": ("{spacing}",) * 3,
    "orthogonal": ("{orthogonal}",) * 3,
}


def route_words(route: str) -> dict[str, str]:
    """Every fix of ``PHRASES`` in ``route``'s words."""
    k = ROUTES.index(route)
    names = {option: name.on(route) for option, name in NAMES.items()}
    return {token: phrases[k].format(**names) for token, phrases in PHRASES.items()}


for _route in ROUTES:
    register_route_words(_route, route_words(_route))
