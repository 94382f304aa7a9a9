"""The command line as pip users expect it: ``--version``, a bad option in one line naming
the nearest option (in a batch manifest too, before its values could pass for the
boundary), a grid written without ``-o`` said to be where it went, and a body's picture
whose colour-bar labels and title stand apart."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT

import pinn_engine
from pinn_engine.command import main

ONE_LINE_HINT = "(pinn-mesh -h lists the options)"


def test_version_prints_the_package_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out == f"pinn-mesh {pinn_engine.__version__}\n"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--sise", "41", "21"], "unknown option --sise; did you mean --size?"),
        ([str(EXAMPLES / "wavy.vtp"), "--sise", "41", "21"], "unknown option --sise"),
        ([str(EXAMPLES / "wavy.vtp"), "--methd=tfi"], "did you mean --method?"),
        ([str(EXAMPLES / "wavy.vtp"), "--method", "magic"], "argument --method: invalid choice"),
    ],
)
def test_a_bad_option_is_one_line_with_the_way_to_the_options(argv, message, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("pinn-mesh: error: ") and err.endswith(f" {ONE_LINE_HINT}\n")
    assert err.count("\n") == 1 and message in err


def test_values_that_look_like_options_are_still_values(tmp_path, capsys):
    out = tmp_path / "g.vts"
    argv = [str(EXAMPLES / "wavy.vtp"), "--method", "tfi", "--size", "11", "6"]
    assert main([*argv, "-o", str(out), "--seed", "-3"]) == 2  # reaches the range check
    assert "pinn-mesh: error: --seed -3: must be" in capsys.readouterr().err
    assert main([*argv, f"-o{out}", "--meth", "tfi"]) == 0  # attached value, unique prefix
    assert out.is_file()


def test_choices_are_read_in_either_case(tmp_path):
    """O-grid, C-grid, TFI, OpenFOAM: names users write in capitals are the same choices."""
    out = tmp_path / "case"
    argv = ["--naca", "0012", "--topology", "C", "--method", "TFI", "--size", "41", "11"]
    assert main([*argv, "-o", str(out), "--format", "OpenFOAM", "--quiet"]) == 0
    assert (out / "constant" / "polyMesh" / "points").is_file()


def test_without_o_the_line_says_where_the_grid_went(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [sys.executable, "-m", "pinn_engine.command", str(EXAMPLES / "fig2.vtp")]
        + ["--method", "tfi", "--size", "11", "6", "--quiet"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "wrote out/fig2_tfi.vts (the default place without -o)\n"
    assert (tmp_path / "out" / "fig2_tfi.vts").is_file()


@pytest.mark.slow  # a 1800 x 640 picture: about 5 s
def test_the_body_picture_keeps_bar_labels_and_title_apart(tmp_path):
    from PIL import Image

    from pinn_engine.routes.pyvista_accessor import pinn_mesh
    from pinn_engine.routes.render import BODY_BAR, render_body_png

    grid = pinn_mesh(None, size=(40, 12), method="tfi", topology="o", naca="0012")
    path = render_body_png(grid, tmp_path / "o.png")  # the documented pictures' size
    pixels = np.asarray(Image.open(path).convert("RGB")).astype(int)
    height, width = pixels.shape[0], pixels.shape[1] // 3  # the trailing-edge panel's bar
    left, right = BODY_BAR["position_x"], BODY_BAR["position_x"] + BODY_BAR["width"]
    top, bottom = 1 - BODY_BAR["position_y"] - BODY_BAR["height"], 1 - BODY_BAR["position_y"]
    inset = 3  # pixels inside the bar's white ground
    box = pixels[
        int(top * height) + inset : int(bottom * height) - inset,
        2 * width + int(left * width) + inset : 2 * width + int(right * width) - inset,
    ]
    text = (box.max(axis=2) < 80).any(axis=1)  # rows with black (text) pixels
    starts = np.flatnonzero(np.diff(text.astype(int)) == 1)  # where a run of text rows starts
    assert len(starts) + int(text[0]) == 2  # the labels' rows, then apart the title's


@pytest.mark.parametrize("flag", ["-o", "--report", "--png"])
def test_an_output_that_cannot_be_written_is_refused_before_meshing(flag, tmp_path, capsys):
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    argv = [str(EXAMPLES / "fig2.vtp"), "-o", str(tmp_path / "g.vts"), "--quiet"]
    argv += [flag, "/proc/nope/x.vts" if flag == "-o" else str(blocked / "x")]
    began = time.perf_counter()
    assert main(argv) == 2
    assert time.perf_counter() - began < 1.0  # no training: refused before meshing
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot be written" in err
    assert not (tmp_path / "g.vts").exists()


def test_help_is_one_screen_without_spec_citations(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    short = capsys.readouterr().out
    assert len(short.splitlines()) <= 85 and "SPEC" not in short
    assert re.search(r"--seed SEED\s+\S", short) and "--help-all" in short
    with pytest.raises(SystemExit):
        main(["--help-all"])
    full = capsys.readouterr().out
    assert "SPEC" not in full and re.search(r"--boundary-fit \{[a-z,]+\}\s+\S", full)
    assert len(full.splitlines()) > len(short.splitlines())


@pytest.mark.slow  # trains (MGNet, two L-BFGS iterations) twice
def test_the_no_compiler_warning_is_one_line_and_quiet_under_quiet(tmp_path, monkeypatch, capsys):
    from pinn_engine.neural.jet import native

    monkeypatch.setattr(native, "PACKAGED_DIR", tmp_path / "no-package")
    monkeypatch.setattr(native, "_compiler", lambda: None)
    aux = ["--method", "mgnet", "--lbfgs", "2", "--size", "11", "6"]  # a network trains
    said = {}
    for quiet in ([], ["--quiet"]):
        native.kernels.cache_clear()
        out = tmp_path / f"g{len(quiet)}.vts"
        assert main([str(EXAMPLES / "fig2.vtp"), *aux, "-o", str(out), *quiet]) == 0
        said[bool(quiet)] = [ln for ln in capsys.readouterr().err.splitlines() if "C++" in ln]
    native.kernels.cache_clear()
    assert len(said[False]) == 1 and said[False][0].startswith("pinn-mesh: no C++ compiler")
    assert said[True] == []
