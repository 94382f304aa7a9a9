"""The blocks of a multi-block grid whose networks cannot win (``kinds.untrained.cannot_win``):
each keeps its elliptic grid, untangled where it folds, and the report says so."""

from __future__ import annotations

import time

import numpy as np

from pinn_engine.starts.untangle import untangle, untangled_report


def start_block(start: np.ndarray, reason: str) -> tuple[np.ndarray, dict]:
    """A multi-block grid's block whose network cannot win: its elliptic grid ``start``,
    untangled where it folds (its side nodes bit for bit), and the block's report."""
    began = time.perf_counter()
    grid = untangle(start)
    report = {"result": "start", "skipped": reason, "largest_node_move": 0.0}
    if grid is not start:
        report["untangled"] = untangled_report(start, grid)
    report.update(seconds=time.perf_counter() - began, lbfgs_iterations=0)
    return (grid if grid is not start else start.copy()), report


def blocks_report(blocks: list[dict], began: float) -> dict:
    """The multi-block report's ``training`` from each block's report: the seconds since
    ``began`` (``time.perf_counter``), the blocks whose network's grid was kept, the blocks."""
    return {
        "seconds": time.perf_counter() - began,
        "network_blocks": sum(b["result"] == "network" for b in blocks),
        "blocks": blocks,
    }


def untrained_blocks(grids: list[np.ndarray], reason: str) -> tuple[list[np.ndarray], dict]:
    """Every block of a multi-block grid at its start (:func:`start_block`), where no block's
    network can win; the grids and the report's ``training``."""
    began = time.perf_counter()
    done = [start_block(grid, reason) for grid in grids]
    return [grid for grid, _ in done], blocks_report([block for _, block in done], began)
