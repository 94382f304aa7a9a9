"""Which option a domain kind takes is declared once (each kind's ``OPTIONS``, gathered in
``job.OPTIONS``), and each option's names on the routes are one table (``routes.names``):
the command line's flags and aliases, pyvista's keywords and the messages' words come from
them."""

from __future__ import annotations

import inspect

import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine import job
from pinn_engine.errors import ROUTE_WORDS, InputError
from pinn_engine.routes.cli import build_parser, main
from pinn_engine.routes.cli.options import ROUTE_OPTIONS
from pinn_engine.routes.cli.parser import option_flags
from pinn_engine.routes.names import NAMES, cli_option, route_words
from pinn_engine.routes.pyvista_accessor.four_sided import pinn_mesh
from pinn_engine.routes.pyvista_accessor.hexa import pinn_mesh_hexa
from pinn_engine.routes.pyvista_accessor.multiblock import pinn_mesh_blocks
from pinn_engine.settings import Settings

DESTS = {a.dest for a in build_parser()._actions if a.option_strings}


def test_every_declared_option_is_one_a_route_takes():
    """A kind's option is a setting, a command-line option or a pyvista keyword (by its one
    name): a declaration cannot name an option no route has."""
    keywords = {
        name
        for function in (pinn_mesh, pinn_mesh_blocks, pinn_mesh_hexa)
        for name in inspect.signature(function).parameters
    }
    known = set(Settings.__dataclass_fields__) | {cli_option(d) for d in DESTS} | keywords
    for kind, options in job.OPTIONS.items():
        assert options <= known, (kind, sorted(options - known))


def test_every_command_line_option_is_taken_by_a_kind():
    """Each option of the command line is one some kind takes, or one every run takes (or
    help and version)."""
    taken = set().union(*job.OPTIONS.values()) | ROUTE_OPTIONS
    stray = {cli_option(d) for d in DESTS} - taken
    assert stray == {"help", "help_all", "version"}, sorted(stray)


@pytest.mark.parametrize(
    "option", sorted(o for o, n in NAMES.items() if n.flag != "--" + o.replace("_", "-"))
)
def test_an_option_by_its_one_name_on_the_command_line(option):
    """Where SPEC 5's flag differs from the option's one name, both are flags of one option,
    and the messages name SPEC 5's."""
    spelled = "--" + option.replace("_", "-")
    action = next(a for a in build_parser()._actions if a.dest == NAMES[option].dest)
    assert action.option_strings[:2] == [NAMES[option].flag, spelled]
    assert option_flags()[NAMES[option].dest] == NAMES[option].flag


def test_the_messages_words_are_the_tables():
    """Every route's words (``errors.ROUTE_WORDS``) are ``routes.names``' and name options
    by the table: a label changed there changes the messages."""
    for route in ("cli", "pyvista", "paraview"):
        assert ROUTE_WORDS[route] == route_words(route)
    assert NAMES["lbfgs_iterations"].label in ROUTE_WORDS["paraview"]["lbfgs"]
    assert InputError("try {lbfgs}").for_route("pyvista").args[0] == (
        "try a larger lbfgs_iterations="
    )


def test_an_option_a_kind_does_not_take_is_refused_on_each_route(tmp_path, capsys):
    """--cells is a multi-block option (``job.only_for``): refused on a four-sided run; a
    body refuses the four-sided domain's --corners, and pyvista's corners=."""
    assert "cells" in job.only_for("blocks", "four-sided", "body")
    assert "corners" in job.only_for("four-sided", "body")
    out = tmp_path / "g.vts"
    assert main([str(EXAMPLES / "fig2.vtp"), "--cells", "0,0=4", "-o", str(out)]) == 2
    assert "--cells" in capsys.readouterr().err
    assert main([str(EXAMPLES / "fig2.vtp"), "--cell-size", "0.1", "-o", str(out)]) == 2
    assert "--cell-size applies to multi-block domains (--blocks)" in capsys.readouterr().err
    argv = ["--naca", "0012", "--topology", "o", "--corners", "0", "1", "2", "3", "-o", str(out)]
    assert main(argv) == 2
    assert "--corners applies to four-sided domains, not to --topology" in capsys.readouterr().err
    assert not out.exists()
    with pytest.raises(InputError, match=r"^corners= applies to four-sided domains, not to topo"):
        pv.PolyData().pinn_mesh(naca="0012", topology="o", corners=[0, 1, 2, 3], method="tfi")
