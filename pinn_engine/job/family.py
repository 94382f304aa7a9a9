"""Family models (SPEC 16) as a job sees them: a member of a run's geometry, a model fitted
on members and their default grids, a member meshed by a saved model."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

import numpy as np

from pinn_engine.kinds.outcome import Outcome
from pinn_engine.kinds.single import Geometry
from pinn_engine.settings import Settings


def family_member(settings: Settings, geometry: Geometry):
    """The family member (``family.Member``) of a four-sided or body geometry."""
    from pinn_engine.family import member_of

    return member_of(settings, geometry.boundary, geometry.aux, geometry.body, geometry.far)


def member_target(member, outcome: Outcome) -> np.ndarray:
    """A member's default grid (``outcome``'s) in the member's family frame."""
    return member.frame.to_unit(outcome.grids[0])


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


def run_family(settings: Settings, geometry: Geometry, family: str | os.PathLike) -> Outcome:
    """Mesh a four-sided domain or a body by the family model saved at ``family``."""
    from pinn_engine.family import mesh_member
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
