"""One meshing job, whichever route asks and whatever the domain kind: ``run(settings,
geometry)``.

Every route (the command line and its batches, the VTK algorithms, and through them pyvista
and ParaView) builds a :class:`~pinn_engine.settings.Settings`, turns its inputs into a
geometry by the adapter of their kind (:func:`kind_of` names it; from files or from VTK
data: :class:`Geometry` of a four-sided domain or a body, :class:`BlocksGeometry` of a
multi-block domain, :class:`HexaGeometry` of a six-faced 3D domain,
:class:`DictionaryGeometry` of a blockMeshDict) and calls :func:`run`,
which finds the geometry's kind in the registry (:data:`REGISTRY`), meshes it by that kind's
run and returns one :class:`Outcome`. What differs
between routes is only how they read inputs and present the outcome, in their own words.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.job.cover import covered, followed, unfolded
from pinn_engine.job.family import (
    family_member,
    family_size,
    fit_family_model,
    load_family,
    member_run,
    member_target,
    run_family,
)
from pinn_engine.job.kind import kind_of
from pinn_engine.job.registry import KINDS, OPTIONS, REGISTRY, Kind, kind_of_geometry, only_for
from pinn_engine.kinds.blocks.run import BlocksGeometry, blocks_from_files, blocks_from_polydata
from pinn_engine.kinds.blocks3d.run import (
    DICTIONARY_METHODS,
    DictionaryGeometry,
    dictionary_from_file,
    dictionary_from_text,
    write_cgns,
    write_unstructured,
)
from pinn_engine.kinds.four_sided.cache import MeshCache
from pinn_engine.kinds.hexa.run import HexaGeometry, hexa_from_file, hexa_from_polydata
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.kinds.single import (
    Geometry,
    geometry_from_files,
    geometry_from_polydata,
    topology_of,
)
from pinn_engine.lazy import lazy_names
from pinn_engine.settings import Settings

if TYPE_CHECKING:
    from pinn_engine.adapt import Field


def run(
    settings: Settings,
    geometry: Geometry | BlocksGeometry | HexaGeometry | DictionaryGeometry,
    progress: Callable[[dict], object] | None = None,
    cache: MeshCache | None = None,
    model: str | os.PathLike | None = None,
    family: str | os.PathLike | None = None,
    field: Field | None = None,
) -> Outcome:
    """Mesh ``geometry`` under ``settings`` by its kind's pipeline; ``progress`` hears the
    stages and the training (returning True cancels, ``errors.STOP`` ends the training with
    its best state so far); a four-sided domain's fitted networks are kept in ``cache``
    (re-used when only the size changes), or the model saved at ``model`` (a four-sided
    domain's or a six-faced domain's) is evaluated instead of training; a four-sided domain
    or a body is meshed by the family model saved at ``family`` (SPEC 16) where given. With
    ``field`` (``adapt.Field``) the 2D grid is then adapted to it (SPEC 14, ``job.adapted``)."""
    kind = kind_of_geometry(geometry)
    if family is not None and not kind.family:
        raise InputError(
            "a family model meshes four-sided domains, O- and C-grids and multi-block domains "
            "in this build, not six-faced domains; mesh without the model",
            str(family),
        )
    if field is not None and not kind.adapts:
        raise InputError("adapting to a field (SPEC 14) applies to 2D domains in this build")
    if family is not None:
        outcome = run_family(settings, geometry, family, progress)
    else:
        outcome = kind.run(settings, geometry, progress, cache, model)
    if kind.covered:
        outcome = covered(outcome, geometry)
    if outcome.kind == "four-sided" and family is None and model is None:
        outcome = followed(outcome, settings)
    if field is not None and settings.adapt_strength != 0:
        from pinn_engine.job.adapted import adapted

        field.check_covers(np.vstack([g.reshape(-1, 2) for g in outcome.grids]))
        if progress is not None:
            progress({"phase": "prepare", "stage": "adapting to the field", "step": 0, "total": 1})
        outcome = adapted(outcome, settings, field, getattr(geometry, "walls", None))
    return unfolded(outcome) if kind.adapts else outcome


__all__ = [
    "DICTIONARY_METHODS",
    "KINDS",
    "OPTIONS",
    "REGISTRY",
    "Kind",
    "kind_of_geometry",
    "only_for",
    "Field",
    "BlocksGeometry",
    "DictionaryGeometry",
    "Geometry",
    "HexaGeometry",
    "MeshCache",
    "Outcome",
    "blocks_from_files",
    "family_member",
    "family_size",
    "fit_family_model",
    "load_family",
    "member_run",
    "member_target",
    "blocks_from_polydata",
    "dictionary_from_file",
    "dictionary_from_text",
    "geometry_from_files",
    "geometry_from_polydata",
    "hexa_from_file",
    "hexa_from_polydata",
    "kind_of",
    "read_field",
    "read_field_file",
    "run",
    "run_family",
    "topology_of",
    "write_cgns",
    "write_unstructured",
]
# the field a grid is adapted to (SPEC 14), read through VTK: imported on first use, so that
# a run that adapts nothing (a blockMeshDict written as an OpenFOAM case) imports no VTK
__getattr__, __dir__ = lazy_names(
    __name__,
    {name: "pinn_engine.adapt" for name in ("Field", "read_field", "read_field_file")},
)
