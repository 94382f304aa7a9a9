"""The hexahedral filter in the ParaView GUI as a new user meets it (Xvfb, xdotool).

``tests/paraview/gui/tour.sh`` gives the hexahedral filter ("PINN hex" in the quick-launch)
an STL and a curve, saves its grid from File > Save Data and opens its "?" help and the
help's search. Its own module, so that ``make test`` runs it beside
``test_paraview_gui.py``'s session (``--dist loadfile``). Skipped without ParaView, Xvfb,
xdotool or ImageMagick (``bash scripts/setup_paraview.sh`` installs them).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import drive_gui, skip_without_gui

pytestmark = [pytest.mark.paraview, pytest.mark.gui]

skip_without_gui()


@pytest.fixture(scope="module")
def tour(tmp_path_factory) -> Path:
    """tests/paraview/gui/tour.sh: the hexahedral filter on the bend's STL and on a curve,
    Time Limit, File > Save Data as CGNS and OpenFOAM, the panel's "?" and the help's search."""
    return drive_gui("tour.sh", tmp_path_factory.mktemp("tour"))


def test_an_stl_meshed_in_the_gui_comes_up_coloured_with_its_input_hidden(tour):
    stl = json.loads((tour / "stl.json").read_text())
    assert stl["error"] == "" and stl["points"] == 13 * 11 * 9
    assert stl["representation"] == "Surface With Edges"
    assert stl["colour"] == ["CELLS", "MaxIncludedAngle"]
    assert stl["inputs_visible"] == {"hexa_bend.stl": 0}  # replaced by the grid
    assert stl["summary"].startswith("elliptic 13x11x9 hexahedral grid")  # Output Messages
    assert "faces face0=jmin" in stl["summary"]


def test_a_curve_given_to_the_hexahedral_filter_stays_in_view_and_is_pointed_on(tour):
    curve = json.loads((tour / "curve.json").read_text())
    assert curve["points"] == 0 and curve["inputs_visible"] == {"fig2.vtp": 1}
    assert "a 2D curve is meshed by PINN Structured Mesh" in curve["error"]


def test_save_data_writes_our_cgns_and_an_openfoam_case_of_the_hexahedral_grid(tour):
    import h5py

    with h5py.File(tour / "bend.cgns", "r") as f:  # ours: a BC_t per side and families
        assert sorted(f["Base/Zone/ZoneBC"]) == sorted(
            ["imin", "imax", "jmin", "jmax", "kmin", "kmax"]
        )
        assert {"imin", "kmax"} <= set(f["Base"])
    boundary = (tour / "bend" / "constant" / "polyMesh" / "boundary").read_text()
    assert "imin" in boundary and "frontAndBack" not in boundary  # not extruded


def test_the_plugin_registers_a_help_page_for_each_of_its_filters(tour):
    # the panel's "?" opens qthelp://<namespace>/<folder>/filters.<proxy name>.html
    registered = json.loads((tour / "result.help.json").read_text())
    assert len(registered) == 1
    pages = next(iter(registered.values()))
    for name in (
        "PINNStructuredMesh",
        "PINNStructuredMeshMultiBlock",
        "PINNStructuredMeshHexahedral",
    ):
        assert f"filters.{name}.html" in pages
    assert "sources.PINNAirfoilSource.html" in pages and "index.html" in pages
    assert (tour / "help.png").stat().st_size > 10_000
    assert (tour / "help_search.png").stat().st_size > 10_000
