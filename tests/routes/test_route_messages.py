"""Input errors name the fix in the words of the route that raised them."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import OutputMessages
from vtkmodules.vtkFiltersSources import vtkPolyLineSource

from pinn_engine.errors import ROUTE_WORDS, InputError
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.routes.pyvista_accessor import pinn_mesh

T = np.linspace(0, 2 * np.pi, 40, endpoint=False)
CIRCLE = np.column_stack([np.cos(T), np.sin(T), np.zeros_like(T)])  # no corner at all
SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)


def algorithm_error(points: np.ndarray, closed: bool) -> str:
    source = vtkPolyLineSource()  # what ParaView's Poly Line Source runs
    source.SetNumberOfPoints(len(points))
    for k, p in enumerate(points):
        source.SetPoint(k, *p)
    source.SetClosed(closed)
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, source.GetOutputPort())
    alg.SetMethod("tfi")
    with OutputMessages(alg, "ErrorEvent") as messages:
        alg.Update()
    assert len(messages.lines) == bool(alg.GetLastError())  # one line per error, or none
    return alg.GetLastError()


def cli_error(points: np.ndarray, tmp_path, capsys, closed: bool = True) -> str:
    poly = pv.lines_from_points(np.vstack([points, points[:1]]) if closed else points)
    path = tmp_path / "b.vtp"
    poly.save(path)
    assert main([str(path), "--method", "tfi", "-o", str(tmp_path / "g.vts")]) == 2
    return capsys.readouterr().err


def test_an_open_polyline_names_the_way_to_close_it_on_each_route(tmp_path, capsys):
    assert "close it (repeat its first point at its end)" in cli_error(
        SQUARE, tmp_path, capsys, closed=False
    )
    with pytest.raises(InputError, match=r"a closed line cell") as info:
        pinn_mesh(pv.lines_from_points(SQUARE), method="tfi")
    assert "--" not in str(info.value)
    assert "tick Closed in the Poly Line Source's properties" in algorithm_error(SQUARE, False)
    assert algorithm_error(SQUARE, True) == ""  # Closed ticked: a grid


def test_missing_corners_are_named_with_each_routes_setting(tmp_path, capsys):
    assert "four point indices (--corners)" in cli_error(CIRCLE, tmp_path, capsys)
    with pytest.raises(InputError, match=r"four point indices \(corners=\)"):
        pinn_mesh(CIRCLE, method="tfi")
    assert "four point indices (Corner Indices)" in algorithm_error(CIRCLE, True)


def test_every_route_has_words_for_every_token():
    keys = {frozenset(words) for words in ROUTE_WORDS.values()}
    assert len(keys) == 1 and {"corners", "close"} <= set(ROUTE_WORDS["cli"])
    error = InputError("name them ({corners})", "b.vtp")
    assert str(error) == "b.vtp: name them (--corners)"
    assert str(error.for_route("paraview")) == "b.vtp: name them (Corner Indices)"
    argued = InputError("use {method:elliptic} or pinn")  # a token taking its argument
    assert str(argued) == "use --method elliptic or pinn"
    assert str(argued.for_route("pyvista")) == 'use method="elliptic" or pinn'
    assert str(argued.for_route("paraview")) == "use Method elliptic or pinn"
