"""The ``pinn-mesh`` command line's options (SPEC 5): the parser, and each setting's flag."""

from __future__ import annotations

import argparse
import difflib
import functools
import re
import sys
from typing import NoReturn

from pinn_engine.routes.names import NAMES, cli_aliases
from pinn_engine.settings import (
    METHODS,
    OBJECTIVES,
    PRESETS,
    Interval,
    Options,
    option_constraints,
)

EXIT_ERROR = 2  # the input or an option is refused (argparse's own status for a bad option)
EXIT_INTERNAL = 3  # a bug: the run failed where no input could make it
EXIT_INTERRUPTED = 130  # Ctrl-C or SIGTERM: the shell's 128 + SIGINT
# Options whose value may name a point X,Y (multi-block items) and so start with a minus
PLACE_OPTIONS = tuple(
    flag for option in ("patches", "spacing", "cells", "grading") for flag in cli_aliases(option)
)
NEGATIVE = re.compile(r"^-\.?\d")  # a value starting with a negative number, not an option


def _joined_places(words: list[str]) -> list[str]:
    """``--patch -0.5,0=wall`` as ``--patch=-0.5,0=wall``: a point item of a place option is
    its value (argparse takes any word starting with a minus, but a plain negative number,
    for an option)."""
    out: list[str] = []
    for word in words:
        if out and out[-1] in PLACE_OPTIONS and NEGATIVE.match(word):
            out[-1] = f"{out[-1]}={word}"
        else:
            out.append(word)
    return out


class _FormatKeys:
    """``--format``'s choices: the keys of the formats registered in ``io.export``, which
    is imported only when they are read (``--format`` given, or the help shown)."""

    def _keys(self) -> tuple[str, ...]:
        from pinn_engine.io.export import FORMATS

        return tuple(FORMATS)

    def __contains__(self, key: object) -> bool:
        return key in self._keys()

    def __iter__(self):
        return iter(self._keys())


def _options(name: str) -> tuple:
    """The values a setting of the constraint table takes (its option's choices)."""
    return option_constraints()[name].values


class _SizeAction(argparse.Action):
    """``--size`` takes NI NJ (2D) or NI NJ NK (a six-faced surface), nothing else."""

    def __call__(self, parser, namespace, values, option_string=None):
        if len(values) not in (2, 3):
            parser.error(f"argument {option_string}: expected NI NJ or NI NJ NK")
        setattr(namespace, self.dest, values)


class _VersionAction(argparse.Action):
    """``--version``: the package's version, read from its metadata only when asked for
    (0.03 s of CPU that every run paid)."""

    def __init__(self, option_strings, dest, help="print the version and exit"):  # noqa: A002
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from pinn_engine._version import __version__

        print(f"pinn-mesh {__version__}")  # on stdout, as argparse's own version action
        parser.exit()


# option groups shown by --help-all only, so that --help is one screen of the common ones
EXPERT_GROUPS = ("training (pinn, mgnet)", "elliptic", "more settings")


class _HelpAllAction(argparse.Action):
    """``--help-all``: every option, the expert groups too."""

    def __init__(self, option_strings, dest, help="show every option and exit"):  # noqa: A002
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        parser.print_help(everything=True)
        parser.exit()


class OneLineParser(argparse.ArgumentParser):
    """argparse's parser whose complaint is one line with the way to the options (not the
    usage block), and which names an unknown option, with the nearest known one, before
    argparse could take the option's values for the boundary."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_ERROR, f"{self.prog}: error: {message} ({self.prog} -h lists the options)\n")

    def format_help(self, everything: bool = False) -> str:
        """The help; without ``everything`` the groups of ``EXPERT_GROUPS`` are counted,
        not listed."""
        if everything:
            return super().format_help()
        groups = self._action_groups
        hidden = [g for g in groups if g.title in EXPERT_GROUPS]
        self._action_groups = [g for g in groups if g not in hidden]
        try:
            text = super().format_help()
        finally:
            self._action_groups = groups
        count = sum(len(g._group_actions) for g in hidden)
        titles = ", ".join(g.title for g in hidden)
        return f"{text}\n{count} more options ({titles}): {self.prog} --help-all\n"

    def print_help(self, file=None, everything: bool = False) -> None:
        self._print_message(self.format_help(everything), file or sys.stdout)

    def parse_known_args(self, args=None, namespace=None):
        args = _joined_places(sys.argv[1:] if args is None else [str(a) for a in args])
        for token in args:
            if token == "--":  # what follows is positional
                break
            if self._unknown_option(token):
                flag = token.split("=", 1)[0]
                longs = [o for o in self._option_string_actions if o.startswith("--")]
                nearest = difflib.get_close_matches(flag, longs, n=1)
                hint = f"; did you mean {nearest[0]}?" if nearest else ""
                self.error(f"unknown option {flag}{hint}")
        return super().parse_known_args(args, namespace)

    def _unknown_option(self, token: str) -> bool:
        """Whether ``token`` looks like an option and names none (nor a unique prefix of
        one, nor a short option with its value attached)."""
        if not token.startswith("-") or token == "-" or self._negative_number_matcher.match(token):
            return False
        flag = token.split("=", 1)[0]
        if flag in self._option_string_actions or token[:2] in self._option_string_actions:
            return False
        return not any(o.startswith(flag) for o in self._option_string_actions)


def build_parser() -> argparse.ArgumentParser:
    """The parser of one run's command line (the batch reads its manifest rows with it too)."""
    p = OneLineParser(
        prog="pinn-mesh",
        description="Structured meshes from a physics-informed neural network: four-sided 2D "
        "blocks, airfoil O- and C-grids (--topology), multi-block 2D domains (--blocks), "
        "hexahedral 3D grids (a six-faced surface), and batches (pinn-mesh batch). The PINN "
        "of Chen et al., with TFI, elliptic and MGNet baselines.",
        epilog="Many cases at once: pinn-mesh batch MANIFEST -o OUTDIR (pinn-mesh batch -h).",
        usage="%(prog)s BOUNDARY [--aux LINES] [--size NI NJ [NK]] [-o OUT] [options]",
    )
    p.add_argument("--help-all", action=_HelpAllAction)
    p.add_argument(
        "boundary",
        nargs="?",
        default=None,
        help="closed boundary (.vtp .vtk .csv .txt; a six-faced surface .vtp .stl), or "
        "a body: an airfoil .dat or two closed polylines",
    )
    p.add_argument(
        "--aux",
        action="append",
        default=[],
        metavar="AUX",
        help="auxiliary lines (.vtp/.vtk/.csv/.txt, repeatable), each from a side to the opposite "
        "one (of a block, with --blocks): the pinn's grid lines follow them",
    )
    p.add_argument(
        "--blocks",
        action="append",
        default=[],
        metavar="EDGES",
        help="block edges (.vtp/.vtk/.csv/.txt, repeatable): mesh a multi-block domain "
        "(OUT.vtm); 'auto': edges proposed from the boundary and its holes",
    )
    p.add_argument(
        "--save-blocks",
        metavar="PATH",
        help="with --blocks: also write the block edges meshed (.vtp, to edit and give "
        "back as --blocks)",
    )
    p.add_argument(
        "--method",
        type=str.lower,  # O-grid, C-grid, TFI: as users write them
        choices=METHODS,
        default=None,
        help="default pinn (with --blocks too: pinn, elliptic or tfi)",
    )
    p.add_argument(
        "--size",
        nargs="+",
        type=int,
        default=None,
        action=_SizeAction,
        metavar="N",
        help="nodes along xi and eta (default 41 21); NI NJ NK for a six-faced surface "
        "with a FaceId array (default 21 21 21)",
    )
    p.add_argument(
        "--seed",
        type=int,
        default=None,
        help="the network's random seed (default 0): the same seed, the same grid",
    )
    p.add_argument("--version", action=_VersionAction)
    p.add_argument(
        "--preset",
        choices=PRESETS,
        default="default",
        help="'paper' reproduces the paper's section 4 settings exactly",
    )
    p.add_argument(
        "-o",
        "--output",
        default=None,
        metavar="OUT.vts",
        help="output grid (default out/<boundary>_<method>.vts), its format by the "
        "extension: .vts .vtk .xyz .cgns .su2 .msh",
    )
    p.add_argument(
        "--format",
        type=str.lower,  # O-grid, C-grid, TFI: as users write them
        choices=_FormatKeys(),
        metavar="FORMAT",  # argparse would list (and so import) the formats at every start
        default=None,
        help="output format instead of the extension, one of %(choices)s (openfoam: -o DIR/ is a "
        "case)",
    )
    p.add_argument(
        *cli_aliases("patches"),
        dest=NAMES["patches"].dest,
        action="append",
        default=[],
        metavar="SIDE=NAME[:TYPE]",
        help="name a side's patch (bottom right top left; imin ... kmax in 3D), TYPE one "
        "of wall inflow outflow farfield symmetry patch; repeatable. With --blocks: "
        "X,Y=NAME (the piece nearest X,Y), boundary=NAME or holeK=NAME",
    )
    p.add_argument(
        "--cells",
        action="append",
        default=[],
        metavar="X,Y=N",
        help="with --blocks: N cells along the chain through the block side nearest X,Y",
    )
    p.add_argument(
        "--extrude",
        type=float,
        default=None,
        metavar="T",
        help="one cell of thickness T in z for .xyz, .cgns, .msh and openfoam",
    )
    p.add_argument(
        "--corners",
        nargs=4,
        type=int,
        metavar="I",
        help="the four corner point indices, instead of automatic detection",
    )
    p.add_argument(
        "--png",
        metavar="PATH",
        help="also render the grid, coloured by MaxIncludedAngle, to this PNG (off-screen)",
    )
    p.add_argument("--report", metavar="PATH", help="also write a JSON report")
    p.add_argument(
        "--adapt",
        metavar="FILE:ARRAY",
        help="move the nodes to where ARRAY of a solution FILE (.foam, .vtu, .vts, .vtm, ...) "
        "changes fast; counts, corners and patches kept (--adapt-strength)",
    )
    p.add_argument(
        "--fail-on-folded",
        action="store_true",
        help="exit with an error (status 2, no output) if any cell of a 3D grid is folded "
        "(a 2D grid with a folded cell is always refused)",
    )
    p.add_argument(
        "--spacing",
        action="append",
        default=[],
        metavar="SIDE=H",
        help="the first grid edge leaving SIDE is H long, growing smoothly away; "
        "repeatable. O- and C-grids: bottom=H; --blocks: PATCH=H or X,Y=H (a block side); "
        "3D: imin ... kmax",
    )
    p.add_argument(
        "--orthogonal",
        metavar="SIDE[,SIDE...]",
        default=None,
        help="grid lines leave these sides at 90 degrees (pinn, elliptic); --blocks: "
        "patch names; 3D: imin ... kmax",
    )
    p.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="no progress output (a warning about folded cells is still printed)",
    )
    g = p.add_argument_group("training (pinn, mgnet)")
    g.add_argument(*cli_aliases("adam_epochs"), type=int, dest="adam_epochs", help="Adam epochs")
    g.add_argument(
        *cli_aliases("lbfgs_iterations"),
        type=int,
        dest="lbfgs_iterations",
        help="L-BFGS iterations",
    )
    g.add_argument(
        *cli_aliases("hidden_layers"), type=int, dest="hidden_layers", help="hidden layers"
    )
    g.add_argument("--neurons", type=int, help="neurons per hidden layer")
    g.add_argument("--lambda2", type=float, help="weight of the auxiliary-line term")
    g.add_argument(
        "--boundary-mode",
        choices=_options("boundary_mode"),
        dest="boundary_mode",
        help="hard: exact boundary by construction; penalty: the paper's term",
    )
    g.add_argument(
        "--boundary-fit",
        choices=_options("boundary_fit"),
        dest="boundary_fit",
        help="with --boundary-mode penalty: the boundary the penalty term samples: "
        "arclength (default: the input polyline exactly) or tree (the paper's decision-tree "
        "fit; the paper extra)",
    )
    g.add_argument(
        "--warm-start",
        choices=_options("warm_start"),
        dest="warm_start",
        help="elliptic (default): start from the converged elliptic grid and keep "
        "the last state no worse than it; none: train from TFI (paper)",
    )
    g.add_argument(
        "--objective",
        choices=OBJECTIVES,
        dest="objective",
        help="pinn: best (default: the lowest worst cell among TFI, the elliptic grid, "
        "their blends and the quality-optimised grid, mean at most 0.5 deg above the "
        "elliptic grid's, lines followed; winslow under --spacing or --orthogonal), "
        "winslow (the Winslow equations) or quality (plus a cell-quality term that lowers "
        "the worst cell's largest angle)",
    )
    g.add_argument("--device", help="torch device: auto, cpu, cuda")
    g.add_argument("--save-model", metavar="PATH", help="save the trained model")
    g.add_argument(
        "--load-model", metavar="PATH", help="evaluate a saved model instead of training"
    )
    g.add_argument(
        "--model",
        metavar="FAMILY",
        help="mesh by a family model (made by pinn-mesh fit): the member's boundary nodes, "
        "its interior in a forward pass; the size defaults to the family's",
    )
    b = p.add_argument_group("O- and C-grids around a body")
    b.add_argument(
        "--topology",
        type=str.lower,  # O-grid, C-grid, TFI: as users write them
        choices=("o", "c"),
        default=None,
        help="o: O-grid (j = 0 on the body, seam at the trailing edge); c: C-grid "
        "with a wake cut (from a sharp trailing edge or a blunt base's middle)",
    )
    b.add_argument(
        "--naca",
        metavar="DDDD",
        default=None,
        help="NACA 4-digit section of chord 1 instead of a file (blunt trailing "
        "edge for --topology o, closed for c)",
    )
    b.add_argument(
        "--farfield",
        type=float,
        default=None,
        metavar="R",
        help="far-field circle of radius R chords about mid-chord (default 15 for a single body)",
    )
    e = p.add_argument_group("elliptic")
    e.add_argument(
        "--elliptic-iterations",
        type=int,
        dest="elliptic_iterations",
        help="N point-Jacobi sweeps from a zero interior (paper); 0 = converge",
    )
    more = p.add_argument_group("more settings")
    more.add_argument(
        "--grading",
        action="append",
        default=[],
        metavar="X,Y=R",
        help="with --blocks: an expansion ratio, as blockMesh's: along the chain through "
        "the block side nearest X,Y, the cell at the side's far end is R times the cell at "
        "its end nearest X,Y",
    )
    _table_options(more, p)
    return p


def _table_options(group, parser: argparse.ArgumentParser) -> None:
    """A flag ``--name-with-dashes`` for every setting of the constraint table that has no
    hand-written option above: a setting added to the table is an option here too."""
    taken = {action.dest for action in parser._actions}
    for name, rule in option_constraints().items():
        if name in taken:
            continue
        flag = "--" + name.replace("_", "-")
        if isinstance(rule, Options):
            group.add_argument(flag, dest=name, choices=rule.values, help=rule.help)
        else:
            kind = rule.kind if isinstance(rule, Interval) else str
            group.add_argument(flag, dest=name, type=kind, help=rule.help)


@functools.cache
def option_flags() -> dict[str, str]:
    """Each option's flag as the command line names it (dest -> its first long flag: SPEC
    5's, ``--epochs`` where ``--adam-epochs`` works too)."""
    return {
        a.dest: next(o for o in a.option_strings if o.startswith("--"))
        for a in build_parser()._actions
        if a.option_strings
    }
