"""The estimator: configure, ``fit`` on a boundary (trains once), ``predict`` at any resolution."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.classical.elliptic import winslow_solve, winslow_sweeps
from pinn_engine.classical.pins import (
    pin_sharp,
    pinned_boundary,
    pinned_lines,
    placed_on_boundary,
)
from pinn_engine.classical.spacing import (
    classical_grid,
    fit_params,
    side_lengths,
    uniform_params,
    working_spacing,
)
from pinn_engine.classical.tfi import tfi_at, tfi_grid
from pinn_engine.errors import (
    NotFittedError,
    PinnMeshError,
    SettingsError,
    TrainingError,
    network_effect,
)
from pinn_engine.geometry.auxlines import AuxLine, crossing_turns, line_distances
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.geometry.boundary_fit import make_fit
from pinn_engine.heap import reuse_freed_memory
from pinn_engine.kinds.four_sided.untrained import StartModel
from pinn_engine.kinds.untrained import cannot_win, start_or_train
from pinn_engine.quality import boundary_nodes, cell_quality, side_report, summary
from pinn_engine.result import MeshResult
from pinn_engine.settings import NEURAL, Settings, grid_size_problem, make_settings
from pinn_engine.starts.warmstart import lattice_for

if TYPE_CHECKING:
    from pinn_engine.kinds.four_sided.model import TrainedModel

Progress = Callable[[dict], bool | None]


class Mesher:
    """Structured mesher for one boundary; ``method`` is pinn, mgnet, tfi or elliptic.

    The neural methods' default training starts from, and is checked against, the elliptic
    grid on ``settings.lattice`` nodes: give the size you will predict (the command line,
    the filter and the accessor do); other sizes are evaluated from the same map, unchecked.

    >>> mesher = Mesher(make_settings("pinn", lattice=(81, 41))).fit(boundary)
    >>> result = mesher.predict(81, 41)
    """

    def __init__(self, settings: Settings | None = None) -> None:
        self.settings = settings or make_settings()

    # Fitted attributes (set by ``fit``, scikit-learn's way): ``boundary_``, ``aux_lines_``
    # (those the method uses), ``model_`` (the trained network; None for tfi and elliptic),
    # ``train_seconds_``.

    def _check_fitted(self) -> None:
        if not hasattr(self, "boundary_"):
            raise NotFittedError("this Mesher is not fitted yet: call fit(boundary) first")

    def fit(
        self,
        boundary: Boundary,
        aux_lines: Sequence[AuxLine] = (),
        progress: Progress | None = None,
    ) -> Mesher:
        """Prepare meshing of ``boundary``; trains the network for pinn and mgnet.

        ``progress(info)`` is called during training; returning True cancels it.
        """
        working_spacing(self.settings.spacing, boundary)  # checked before any work
        pinn = self.settings.method == "pinn"
        followed = aux_lines if pinn else ()
        # a node on every sharp vertex inside a side and every followed line's end, at the
        # start's lattice
        boundary = pinned_boundary(boundary, *lattice_for(*self.settings.lattice), followed)
        self.boundary_ = boundary
        self.aux_lines_ = pinned_lines(followed, boundary)
        self.model_ = None
        self.train_seconds_ = 0.0
        if self.settings.method in NEURAL:
            aux, settings = self.aux_lines_, self.settings

            def trained() -> TrainedModel:
                began = time.perf_counter()
                from pinn_engine.kinds.four_sided.problem import (
                    train,  # torch: imported only to train
                )

                imported = time.perf_counter()
                model = train(boundary, aux, settings, progress)
                model.info["timings"]["import"] = imported - began
                return model

            self.model_ = start_or_train(
                cannot_win(settings, aux),
                lambda reason: StartModel.of(boundary, aux, settings, reason),
                trained,
            )
            # the network's training alone: 0 where none was trained (its start's time is
            # the report's timings["start"])
            self.train_seconds_ = float(self.model_.info["timings"]["training"])
            self.model_.info["train_seconds"] = self.train_seconds_
        return self

    def save(self, path: str | os.PathLike) -> None:
        """Save the trained network (pinn and mgnet only)."""
        self._check_fitted()
        if self.model_ is None:
            raise PinnMeshError(f"method {self.settings.method} has no trained model to save")
        self.model_.save(path)

    @classmethod
    def load(cls, path: str | os.PathLike, boundary: Boundary) -> Mesher:
        """A fitted mesher from a saved model; ``boundary`` must be the one it was trained on."""
        from pinn_engine.kinds.four_sided.model import TrainedModel

        model = TrainedModel.load(path, boundary)
        mesher = cls(model.settings)
        mesher.boundary_, mesher.aux_lines_, mesher.model_ = model.mapping.boundary, [], model
        mesher.train_seconds_ = float(model.info.get("train_seconds", 0.0))
        return mesher

    def predict(
        self, ni: int, nj: int, unit: np.ndarray | None = None, *, on_boundary: bool = True
    ) -> MeshResult:
        """The grid at ``ni`` x ``nj`` nodes; feed-forward for the neural methods. ``unit``:
        that grid (working frame) where already evaluated (a size change's guard).
        ``on_boundary``: the soft boundary mode's nodes placed on the boundary (the grid a
        route writes); False gives that network's own map, as the paper measures it."""
        self._check_fitted()
        problem = grid_size_problem(ni, nj)
        if problem:
            raise SettingsError(f"grid size {ni} x {nj}: {problem}")
        with reuse_freed_memory():
            start = time.perf_counter()
            unit = self._grid_unit(ni, nj) if unit is None else unit
            mesh_seconds = time.perf_counter() - start
            if not np.all(np.isfinite(unit)):
                raise TrainingError(
                    f"the {self.settings.method} grid has non-finite grid "
                    "points (training failed); try another seed or fewer epochs"
                )
            placed = None
            if on_boundary and self.model_ is not None and self.settings.boundary_mode == "penalty":
                placed = float(self.boundary_.deviation(boundary_nodes(unit)).max())
                unit = placed_on_boundary(unit, self.boundary_)
            deviation = float(self.boundary_.deviation(boundary_nodes(unit)).max())
            points = self.boundary_.frame.to_user(unit)
            cells = cell_quality(points)
            quality_seconds = time.perf_counter() - start - mesh_seconds
        report = {
            "method": self.settings.method,
            "size": [ni, nj],
            "settings": self.settings.to_dict(),
            "train_seconds": self.train_seconds_,
            "mesh_seconds": mesh_seconds,
            "quality": summary(cells, deviation),
            "source": self.boundary_.source,
            "aux_lines": [a.name for a in self.aux_lines_],
            "aux_line_distance": line_distances(unit, self.aux_lines_, self.boundary_.diagonal),
            "aux_line_turn": crossing_turns(unit, self.aux_lines_),
            "sides": side_report(unit, self.boundary_.frame.scale),
        }
        if placed is not None:  # the soft boundary's network only approached the sides
            report["boundary_placed"] = {"network_deviation": placed}
        timings = {"start": 0.0, "training": 0.0}
        if self.model_ is not None:
            report["training"] = self.model_.info
            timings.update(self.model_.info.get("timings", {}))
        report["timings"] = {**timings, "mesh": mesh_seconds, "quality": quality_seconds}
        choice = network_effect(report)
        if choice:  # the summary's line, in the report for the routes without one (pyvista)
            report["choice"] = choice
        history = self.model_.history if self.model_ is not None else {}
        return MeshResult(
            points=points, report=report, history=history, cells=cells, plane=self.boundary_.plane
        )

    def _grid_unit(self, ni: int, nj: int) -> np.ndarray:
        """The grid (working frame) with a node on every sharp vertex inside a side where
        the side's nodes allow it (``pins.pin_sharp``)."""
        s = self.settings
        if s.spacing or (s.orthogonal and s.method == "elliptic"):
            return self._spaced_grid_unit(ni, nj)
        uniform = uniform_params(ni, nj)
        params = pin_sharp(self.boundary_, uniform)
        at = None if params is uniform else params
        if self.model_ is not None:
            return self.model_.grid(ni, nj) if at is None else self.model_.grid(ni, nj, params=at)
        # classical methods always place boundary nodes exactly on the input polyline
        if at is None:
            base = tfi_grid(make_fit("arclength", self.boundary_).sample, ni, nj)
        else:
            base = tfi_at(self.boundary_)(at)
        if s.method == "tfi":
            return base
        if s.elliptic_iterations:
            return winslow_sweeps(base, s.elliptic_iterations, zero_interior=True)
        return winslow_solve(base)[0]

    def _spaced_grid_unit(self, ni: int, nj: int) -> np.ndarray:
        """The grid under ``spacing``/``orthogonal`` (SPEC 7, spacing.py): node parameters
        iterated until every first edge has its length; the neural map is evaluated there."""
        s = self.settings
        spacing = working_spacing(s.spacing, self.boundary_)

        def pin(params: np.ndarray) -> np.ndarray:
            return pin_sharp(self.boundary_, params)

        if self.model_ is None:
            return classical_grid(self.boundary_, ni, nj, s.method, spacing, s.orthogonal, pin=pin)[
                1
            ]
        mapping = self.model_.mapping
        nodes = None if mapping.warm is None else mapping.warm.nodes
        if nodes is not None and (len(nodes[0]), len(nodes[1])) == (ni, nj):
            # the nodes of the orthogonal start (starts/warmstart.py): first rows normal to the
            # walls and as far from them as the spacing asks
            return mapping.grid(ni, nj, params=pin(np.stack(np.meshgrid(*nodes), axis=-1)))
        return fit_params(
            lambda p: mapping.grid(ni, nj, params=p),
            spacing,
            ni,
            nj,
            side_lengths(self.boundary_),
            pin,
        )[1]
