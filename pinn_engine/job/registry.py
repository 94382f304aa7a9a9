"""The domain kinds as one registry: which geometry each kind's run takes and what it offers.

``job.run`` finds a geometry's kind here and asks the kind alone what it takes (a family
model, a field to adapt to) and whether its outcome is checked to fill the domain drawn; a
kind added is one entry, not a branch in the orchestrator.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

from pinn_engine.errors import InputError
from pinn_engine.kinds import blocks, blocks3d, body, four_sided, hexa
from pinn_engine.kinds.blocks.run import BlocksGeometry, run_blocks
from pinn_engine.kinds.blocks3d.run import DictionaryGeometry, run_dictionary
from pinn_engine.kinds.four_sided.cache import MeshCache
from pinn_engine.kinds.hexa.run import HexaGeometry, run_hexa
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.kinds.single import Geometry, run_single
from pinn_engine.settings import Settings

Progress = Callable[[dict], object] | None


@dataclass(frozen=True)
class Kind:
    """A domain kind (or two sharing a geometry: four-sided and body) as ``job.run`` meshes
    it: its ``names`` (what ``Outcome.kind`` says), the ``geometry`` type its ``run`` takes,
    whether its outcome is checked to fill the domain drawn (``covered``, ``job.cover``),
    whether it is meshed by a family model (``family``, SPEC 16) and adapted to a field
    (``adapts``, SPEC 14), and the options each of its ``names`` takes (``options``: their
    packages' ``OPTIONS``)."""

    names: tuple[str, ...]
    geometry: type
    run: Callable[[Settings, object, Progress, MeshCache | None, str | os.PathLike | None], Outcome]
    covered: bool
    family: bool
    adapts: bool
    options: tuple[frozenset[str], ...]


REGISTRY = (
    Kind(
        ("four-sided", "body"),
        Geometry,
        run_single,
        True,
        True,
        True,
        (four_sided.OPTIONS, body.OPTIONS),
    ),
    Kind(
        ("blocks",),
        BlocksGeometry,
        lambda settings, geometry, progress, cache, model: run_blocks(settings, geometry, progress),
        True,
        True,
        True,
        (blocks.OPTIONS,),
    ),
    Kind(
        ("hexa",),
        HexaGeometry,
        lambda settings, geometry, progress, cache, model: run_hexa(
            settings, geometry, progress, model
        ),
        False,
        False,
        False,
        (hexa.OPTIONS,),
    ),
    Kind(
        ("dictionary",),
        DictionaryGeometry,
        lambda settings, geometry, progress, cache, model: run_dictionary(
            settings, geometry, progress
        ),
        False,
        False,
        False,
        (blocks3d.OPTIONS,),
    ),
)
# The domain kinds (SPEC 5, 9, 10, 11, 15): a four-sided block, an O- or C-grid round a body,
# a multi-block 2D domain, a six-faced 3D domain, a blockMeshDict's blocks
KINDS = tuple(name for kind in REGISTRY for name in kind.names)
# The options each kind takes, by its one name (settings' and the inputs'; routes/names.py
# words them on each route)
OPTIONS = {name: opts for kind in REGISTRY for name, opts in zip(kind.names, kind.options)}


def only_for(kind: str, *others: str) -> list[str]:
    """The options ``kind`` takes and none of ``others`` does, sorted."""
    return sorted(OPTIONS[kind].difference(*(OPTIONS[o] for o in others)))


def kind_of_geometry(geometry: object) -> Kind:
    """The registered kind whose run takes ``geometry``."""
    for kind in REGISTRY:
        if isinstance(geometry, kind.geometry):
            return kind
    raise InputError(f"no domain kind meshes a {type(geometry).__name__}")
