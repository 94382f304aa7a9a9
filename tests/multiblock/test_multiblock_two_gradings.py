"""Two gradings on one chain from its two ends (SPEC 10's --spacing X,Y=H on both walls of
a channel, as blockMesh dicts grade a channel towards both walls): the sides along both
gradings are stretched from both ends, not by the last item alone."""

from __future__ import annotations

import json

import numpy as np
import pyvista as pv

from pinn_engine.routes.cli import main

RING = [(0, 0), (4, 0), (4, 1), (0, 1)]  # a channel, cut into two blocks at x = 1
EDGE = [(1, 0), (1, 1)]
CELLS = ["--cells=0.5,0=10", "--cells=3,0=30", "--cells=0,0.5=30"]
WALL = 0.005  # first edge at both walls (the even cell is 1/30)


def _polydata(lines: list, closed: bool) -> pv.PolyData:
    points, cells = [], []
    for line in lines:
        ids = [len(points) + k for k in range(len(line))]
        cells += [len(ids) + closed, *ids, *ids[:closed]]
        points += [(x, y, 0.0) for x, y in line]
    return pv.PolyData(np.array(points, dtype=float), lines=np.array(cells))


def test_both_walls_graded_give_both_first_edges_on_every_side(tmp_path):
    """The inlet and the outlet start at WALL at both walls (the inlet kept
    the even cell at its bottom when the top wall's item came last), and the rows stay
    straight: worst MaxIncludedAngle under 100 degrees (134 with the bottom one lost)."""
    _polydata([RING], True).save(tmp_path / "channel.vtp")
    _polydata([EDGE], False).save(tmp_path / "edge.vtp")
    out, report = tmp_path / "channel.vtm", tmp_path / "report.json"
    args = [str(tmp_path / "channel.vtp"), "--blocks", str(tmp_path / "edge.vtp"), *CELLS]
    args += [f"--spacing=2,0={WALL}", f"--spacing=2,1={WALL}", "--method", "elliptic"]
    assert main([*args, "--quiet", "--report", str(report), "-o", str(out)]) == 0
    quality = json.loads(report.read_text())["quality"]
    assert quality["folded_cells"] == 0 and quality["worst_max_angle"] < 100.0
    checked = 0
    for block in pv.read(out):
        ni, nj, _ = block.dimensions
        xy = block.points[:, :2].reshape(nj, ni, 2)
        for column in (xy[:, 0], xy[:, -1]):
            if np.ptp(column[:, 0]) == 0 and column[0, 0] in (0.0, 4.0):  # inlet, outlet
                ends = np.array([column[1, 1] - column[0, 1], column[-1, 1] - column[-2, 1]])
                assert np.all(np.abs(ends / WALL - 1) < 0.02), ends
                checked += 1
    assert checked == 2
