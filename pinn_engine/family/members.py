"""A member of a family as its model sees it: its kind, its boundary nodes placed exactly as
its own run places them, and a base grid on them, in the family's frame.

- Four-sided: the arc-length TFI of the boundary, each sharp vertex inside a side a node (the
  nodes and base of the default run, ``kinds.four_sided.untrained.StartModel``), in the
  boundary's unit-box working frame.
- Body (O- or C-grid): the member's reference grid (``bodygrid.layout``: its wall, first row
  and far field nodes, which its own run's grids keep, and the rows marched between them, from
  which its own run solves its elliptic grid), in the frame of its chord: mid-chord at the
  origin, chord 1. Its elliptic grid (its own run's start, ``kinds.body.mesh.mesh_body``) is
  solved only where asked (:meth:`Member.body_start`): a certified model grid needs none.
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
    the four-sided ``boundary``, or the body's ``layout`` (``bodygrid.Layout``), ``body``,
    far field ``far`` and the run's settings ``run`` (its elliptic ``start``, a
    :class:`MeshResult`, once solved: :meth:`body_start`); ``settings``: the run's settings
    that make a family (``model.FAMILY_KEYS``); ``optimised``: whether its own run's grid is
    its nodes' optimum under the quality objective (the default's,
    ``Settings.quality_objective``)."""

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
    elliptic: np.ndarray | None = None  # its elliptic grid (family frame), once solved
    layout: object | None = None  # a body's bodygrid.Layout
    run: Settings | None = None  # a body's run settings (its start's)

    @property
    def size(self) -> tuple[int, int]:
        return self.base.shape[1], self.base.shape[0]

    def body_start(self) -> MeshResult:
        """A body's own start: its elliptic grid on its layout (``mesh_body``), solved once;
        ``elliptic`` is then that grid in the family's frame."""
        if self.start is None:
            from pinn_engine.kinds.body.mesh import mesh_body

            ni, nj = self.size
            self.start = mesh_body(
                self.body, self.far, self.topology, "elliptic", ni, nj, self.run,
                self.run.wall_spacing, layout=self.layout,
            )  # fmt: skip
            self.elliptic = self.frame.to_unit(self.start.points)
        return self.start


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
    from pinn_engine.kinds.body.mesh import body_layout
    from pinn_engine.kinds.body.untrained import WALL, body_cannot_win

    lay = body_layout(body, far, settings.topology, settings.method, ni, nj, settings.wall_spacing)
    frame = Frame(origin=np.asarray(body.mid_chord, dtype=float), scale=float(body.chord))
    base = frame.to_unit(lay.reference)
    shared = family_settings(settings)
    # its own run optimises its nodes (the default objective), a thin-walled member's beyond
    # its boundary layer (quality_start.body_held_rows)
    optimised = body_cannot_win(settings, 0.0) == WALL
    return Member(
        "body", settings.topology, base, frame, body.source, None, None, body, far, shared,
        optimised, layout=lay, run=settings,
    )  # fmt: skip
