"""A member of a family as its model sees it: its kind, its boundary nodes placed exactly as
its own run places them, and a base grid on them, in the family's frame.

- Four-sided: the arc-length TFI of the boundary, each sharp vertex inside a side a node (the
  nodes and base of the default run, ``kinds.four_sided.untrained.StartModel``), in the
  boundary's unit-box working frame.
- Body (O- or C-grid): the member's elliptic grid (``kinds.body.mesh.mesh_body``: the wall and far
  field nodes of ``bodygrid.layout``, the start of the default run), in the frame of its
  chord: mid-chord at the origin, chord 1.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pinn_engine.classical.pins import pinned_boundary
from pinn_engine.classical.tfi import tfi_grid
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Frame
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.kinds.body.settings import BodySettings
from pinn_engine.result import MeshResult
from pinn_engine.settings import DEFAULT_SIZE, Settings
from pinn_engine.starts.warmstart import lattice_for

KINDS = ("four-sided", "body")
# The settings that make a family: its members share them, and a member meshed by its model
# must ask for the same (its counts, its kind and what places its nodes)
FAMILY_KEYS = ("topology", "size", "farfield", "spacing", "orthogonal", "objective", "method")


def family_settings(settings: Settings) -> dict:
    """The settings of ``settings`` that a family's members share (``FAMILY_KEYS``), as
    lists and numbers (what a saved model holds); a four-sided member's far field is a
    body's default, as saved models hold it."""
    out = {}
    for key in FAMILY_KEYS:
        value = getattr(settings, key, getattr(BodySettings, key))
        if key == "size":
            value = settings.size or DEFAULT_SIZE
        if isinstance(value, tuple):
            value = [list(v) if isinstance(v, tuple) else v for v in value]
        out[key] = value
    return out


@dataclass
class Member:
    """A member: ``kind``, ``topology`` (``none``, ``o`` or ``c``), ``base`` (nj, ni, 2) in the
    family's frame, ``frame`` (to the user's coordinates), ``source``, and what its kind keeps:
    the four-sided ``boundary``, or the body's elliptic ``start`` (a :class:`MeshResult`),
    ``body`` and far field ``far``; ``settings``: the run's settings that make a family
    (``model.FAMILY_KEYS``); ``optimised``: whether its own run's grid is its nodes'
    optimum under the quality objective (the default's, ``Settings.quality_objective``)."""

    kind: str
    topology: str
    base: np.ndarray
    frame: Frame
    source: str
    boundary: object | None = None  # geometry.boundary.Boundary
    start: MeshResult | None = None
    body: object | None = None  # bodies.airfoil.Body
    far: object | None = None  # bodies.airfoil.FarField
    settings: dict | None = None  # the run's settings that a family's members share
    optimised: bool = False  # its own run optimises its nodes (the default objective)
    elliptic: np.ndarray | None = None  # a four-sided member's elliptic grid, once solved

    @property
    def size(self) -> tuple[int, int]:
        return self.base.shape[1], self.base.shape[0]


def member_of(
    settings: Settings,
    boundary=None,
    aux: Sequence = (),
    body=None,
    far=None,
) -> Member:
    """The member of a run's geometry under ``settings``: a four-sided ``boundary`` or a
    ``body`` in its far field ``far``. Auxiliary lines, a spacing or orthogonal sides of a
    four-sided domain are refused in one line (their grids place nodes otherwise)."""
    ni, nj = settings.size or DEFAULT_SIZE
    if settings.topology == "none":
        if aux or settings.spacing or settings.orthogonal:
            raise InputError(
                "a family model meshes four-sided domains without auxiliary lines, "
                "{spacing} or {orthogonal} in this build; drop them (or mesh without the model)",
                boundary.source,
            )
        # a node on every sharp vertex inside a side, as the member's own run places them
        # (Mesher.fit: classical/pins.py at the start's lattice)
        boundary = pinned_boundary(boundary, *lattice_for(*settings.lattice))
        base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)
        shared = family_settings(settings)
        return Member(
            "four-sided", "none", base, boundary.frame, boundary.source, boundary,
            settings=shared, optimised=settings.quality_objective,
        )  # fmt: skip
    from pinn_engine.kinds.body.mesh import mesh_body

    start = mesh_body(
        body, far, settings.topology, "elliptic", ni, nj, settings, settings.wall_spacing
    )
    from pinn_engine.kinds.body.untrained import WALL, body_cannot_win

    frame = Frame(origin=np.asarray(body.mid_chord, dtype=float), scale=float(body.chord))
    base = frame.to_unit(start.points)
    shared = family_settings(settings)
    # its own run optimises its nodes (the default objective); the wall cells' aspect is not
    # known here, so a thin-walled member (whose run keeps its elliptic grid) is optimised
    # too, and its ranking keeps it no worse than that grid
    optimised = body_cannot_win(settings, 0.0) == WALL
    return Member(
        "body", settings.topology, base, frame, body.source, None, start, body, far, shared,
        optimised,
    )  # fmt: skip
