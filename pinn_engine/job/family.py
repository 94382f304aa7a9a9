"""Family models (SPEC 16) as a job sees them: a member of a run's geometry, a model fitted
on members and their default grids, a member meshed by a saved model."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from pinn_engine.kinds.blocks.run import BlocksGeometry, run_blocks
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.kinds.single import Geometry
from pinn_engine.settings import Settings


def family_member(settings: Settings, geometry: Geometry):
    """The family member (``family.Member``) of a four-sided or body geometry."""
    from pinn_engine.family import member_of

    return member_of(settings, geometry.boundary, geometry.aux, geometry.body, geometry.far)


def member_run(settings: Settings, geometry: Geometry | BlocksGeometry) -> tuple[Outcome, object]:
    """A member's own run (its default grid, ``job.run``) and its family member; a
    multi-block member's is its run's blocking and layout."""
    from pinn_engine.family import blocks_member, refuse_blocks_options
    from pinn_engine.geometry.boundary import Frame
    from pinn_engine.job import run

    if not isinstance(geometry, BlocksGeometry):
        return run(settings, geometry), family_member(settings, geometry)
    g = geometry
    refuse_blocks_options(g.aux, g.walls, g.gradings, g.source)
    found = []

    class Recorder:  # multiblock.mesh.StartNodes: the layout's own start, the member noted
        def __call__(self, topo, lay) -> None:
            frame = Frame.around(topo.lines.rings[0])
            found.append(blocks_member(settings, lay, g.source, frame))

        def note(self, report: dict) -> None:
            report.pop("solve_start")

    outcome = run(settings, replace(geometry, start=Recorder()))
    return outcome, found[0]


def member_target(member, outcome: Outcome) -> np.ndarray:
    """A member's default grid (``outcome``'s) in the member's family frame; a multi-block
    member's unique nodes, from its blocks' grids."""
    if member.kind != "blocks":
        return member.frame.to_unit(outcome.grids[0])
    points = np.array(member.layout.points)
    for ids, grid in zip(member.layout.ids, outcome.grids):
        points[ids] = grid
    return member.stacked(member.frame.to_unit(points))


def fit_family_model(
    members: Sequence,
    targets: Sequence[np.ndarray],
    options: str = "",
    epochs: int | None = None,
    seed: int = 0,
    progress: Callable[[dict], object] | None = None,
):
    """A ``family.FamilyModel`` fitted on ``members`` and their default grids ``targets``."""
    from pinn_engine.family import FamilyModel
    from pinn_engine.family.model import EPOCHS

    epochs = EPOCHS if epochs is None else epochs
    return FamilyModel.fit(members, targets, options, epochs, seed, progress)


def load_family(path: str | os.PathLike):
    """The family model saved at ``path`` (``pinn-mesh fit``), checked."""
    from pinn_engine.family import load_family as load

    return load(path)


def family_size(path: str | os.PathLike) -> tuple[int, int]:
    """The node counts of the family model at ``path``: a run with the model that names no
    size takes them."""
    from pinn_engine.family import family_size as size

    return size(path)


def run_family(
    settings: Settings,
    geometry: Geometry | BlocksGeometry,
    family: str | os.PathLike,
    progress: Callable[[dict], object] | None = None,
) -> Outcome:
    """Mesh a four-sided domain, a body or a multi-block domain by the family model saved at
    ``family`` (a multi-block domain: its own run, solved from the model's nodes)."""
    from pinn_engine.family import BlocksStart, mesh_member

    if isinstance(geometry, BlocksGeometry):
        start = BlocksStart(family, settings, geometry)
        return run_blocks(settings, replace(geometry, start=start), progress)
    from pinn_engine.io.export import patch_names
    from pinn_engine.io.export.patches import body_patch_names as body_patches
    from pinn_engine.io.pipeline import to_vtk

    if settings.topology == "none":
        names = patch_names(geometry.patches)
    else:
        names = patch_names(geometry.patches, body_patches(settings.topology))
    result = mesh_member(
        family, settings, geometry.boundary, geometry.aux, geometry.body, geometry.far
    )
    kind = "four-sided" if settings.topology == "none" else "body"
    grid = to_vtk(result, names)
    return Outcome(kind, grid, result.report, [result.points], result.history, False)
