"""The ParaView GUI as a user drives it (Xvfb, xdotool): auxiliary lines, stopping and
the abort button.

``tests/paraview/gui/drive.sh`` selects the boundary and the auxiliary-line source in the
Pipeline Browser, types "PINN" in the quick-launch (PINN Structured Mesh must be the one it
picks), and later stops a long training with SIGUSR1, another with the panel's Time Limit
and a third with the progress bar's abort button (``test_paraview_tour.py`` drives the
hexahedral filter). Skipped without ParaView, Xvfb, xdotool or ImageMagick
(``bash scripts/setup_paraview.sh`` installs them).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import drive_gui, skip_without_gui

pytestmark = [pytest.mark.paraview, pytest.mark.gui]

skip_without_gui()


@pytest.fixture(scope="module")
def gui(tmp_path_factory) -> Path:
    return drive_gui("drive.sh", tmp_path_factory.mktemp("gui"))


def test_pinn_in_the_quick_launch_meshes_both_selected_sources_with_aux_lines(gui):
    result = json.loads((gui / "aux_lines.json").read_text())
    assert result["error"] == ""
    assert result["inputs"] == ["fig2.vtp", "fig2_aux.vtp"]
    assert result["points"] == 41 * 21
    assert len(result["aux_lines"]) == 2  # fig2_aux.vtp holds two polylines
    assert (gui / "aux_lines.png").stat().st_size > 10_000
    assert (gui / "quick_launch.png").stat().st_size > 10_000  # Ctrl+Space "PINN": the list
    # ParaView started without an error of its own (a plugin XML slip opens Output Messages
    # over the window, as a wrongly placed widget decorator once did)
    assert "ERR|" not in (gui / "aux_lines.log").read_text()


def test_a_long_training_stopped_by_signal_gives_its_best_grid_and_paraview_goes_on(gui):
    result = json.loads((gui / "stop.json").read_text())
    assert result["error"] == "" and result["points"] == 41 * 21
    assert "a stop was asked during adam" in result["warning"]
    assert "the grid of the best state so far is produced" in result["warning"]
    assert (gui / "alive").read_text().strip() == "yes"


def test_the_time_limit_ends_a_long_training_with_its_best_grid(gui):
    result = json.loads((gui / "limit.json").read_text())
    assert result["error"] == "" and result["points"] == 41 * 21
    assert "its time limit of 4 s ran out during adam" in result["warning"]
    assert "a larger Time Limit (0: none)" in result["warning"]


def test_a_grid_after_a_failed_apply_is_shown_with_edges_coloured_by_max_angle(gui):
    # ParaView picks a display's colour array when it creates the display;
    # after a failed first Apply (an empty output) the plugin colours it when the grid comes
    failed = json.loads((gui / "failed_display.json").read_text())
    assert failed["points"] == 0 and "boundary input" in failed["error"]
    fixed = json.loads((gui / "fixed_display.json").read_text())
    assert fixed["points"] == 41 * 21 and fixed["error"] == ""
    assert fixed["representation"] == "Surface With Edges"
    assert fixed["colour"] == ["CELLS", "MaxIncludedAngle"]
    log = (gui / "failed.log").read_text()
    assert "SIGSEGV" not in log and "Traceback" not in log


def test_the_abort_button_stops_the_training_and_no_click_is_replayed(gui):
    """The training runs in a worker thread while ParaView's event loop goes on: the window
    repaints, the progress bar's abort button ends the training at once with its best
    grid, and a click on another source's row made meanwhile is dropped, not replayed."""
    result = json.loads((gui / "abort.json").read_text())
    assert result["error"] == "" and result["points"] == 41 * 21
    assert "a stop was asked" in result["warning"]
    clicked, done = (float((gui / name).read_text()) for name in ("abort_clicked", "abort_done"))
    # at the next progress step (50 Adam epochs; drive.sh clicks once the bar says
    # "training"): 1.2 s measured at load average 4-6
    assert done - clicked < 5
    display = json.loads((gui / "abort_display.json").read_text())
    assert display["selected"] == "PINNStructuredMesh"  # the click on fig2_aux.vtp dropped
    assert (gui / "training.png").stat().st_size > 10_000
