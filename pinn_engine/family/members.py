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
- Multi-block: its blocks' grids of its blocking's layout (``multiblock.layout``: each
  piece's nodes at equal arc length, each block's interior the TFI of its sides), from which
  its own run solves its elliptic grid, stacked in the family's block order and orientation
  (:func:`aligned`), in the outer boundary's unit-box frame; its ``topology`` names its
  blocking (the blocks' counts and shared nodes), which every member shares.
"""

from __future__ import annotations

import hashlib
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

KINDS = ("four-sided", "body", "blocks")
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
    if hasattr(settings, "interfaces"):  # a multi-block run's: its interface nodes solved
        out["interfaces"] = settings.interfaces
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
    layout: object | None = None  # a body's bodygrid.Layout, a multi-block's multiblock Layout
    run: Settings | None = None  # a body's run settings (its start's)
    drawn: np.ndarray | None = None  # a multi-block member's block side nodes in its base
    ids: list | None = None  # a multi-block member's blocks' node ids, the family's order

    @property
    def size(self) -> tuple[int, int]:
        """(ni, nj) of a grid; a multi-block member's stacked and unique nodes."""
        if self.kind == "blocks":
            return len(self.base), len(self.layout.points)
        return self.base.shape[1], self.base.shape[0]

    def unique(self, stacked: np.ndarray) -> np.ndarray:
        """A multi-block member's unique nodes of ``stacked`` (its base's shape), its layout's
        where no block holds them."""
        points = np.array(self.frame.to_unit(self.layout.points))
        points[np.concatenate([k.ravel() for k in self.ids])] = stacked
        return points

    def stacked(self, unique: np.ndarray) -> np.ndarray:
        """A multi-block member's ``unique`` nodes (N, 2) stacked as its base."""
        return unique[np.concatenate([k.ravel() for k in self.ids])]

    def blocks_of(self, stacked: np.ndarray) -> list[np.ndarray]:
        """A multi-block member's ``stacked`` nodes as its blocks' grids (nj, ni, 2)."""
        ends = np.cumsum([k.size for k in self.ids])[:-1]
        return [b.reshape(*k.shape, 2) for b, k in zip(np.split(stacked, ends), self.ids)]

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


def blocks_member(
    settings: Settings, lay, source: str, frame: Frame, corners: list | None = None
) -> Member:
    """The member of a multi-block run's layout ``lay`` (``multiblock.layout.Layout``) under
    ``settings``, in ``frame`` (its outer boundary's unit box), its blocks aligned with
    ``corners`` (the family's, :func:`aligned`; None: as laid out): its base is its blocks'
    layout grids stacked, block after block in the family's order and orientation, its
    shared nodes in each block that holds them."""
    return _blocks(lay, frame, corners, source, family_settings(settings))


def realigned(member: Member, corners: list) -> Member:
    """``member`` (multi-block) with its blocks aligned with ``corners`` (:func:`aligned`)."""
    return _blocks(member.layout, member.frame, corners, member.source, member.settings)


def _blocks(lay, frame: Frame, corners: list | None, source: str, shared: dict) -> Member:
    """:func:`blocks_member` of the family's ``shared`` settings."""
    ids = aligned(frame.to_unit(lay.points), lay.ids, corners)
    stacked = np.concatenate([k.ravel() for k in ids])
    # the blocking's topology: the blocks' counts and which of their nodes are one node
    _, first, inverse = np.unique(stacked, return_index=True, return_inverse=True)
    shape = [k.shape for k in ids], first[inverse].tobytes()
    digest = hashlib.sha1(repr(shape).encode()).hexdigest()[:8]
    cells = sum((a - 1) * (b - 1) for a, b in shape[0])
    sides = np.concatenate([_side_mask(k.shape).ravel() for k in ids])
    return Member(
        "blocks", f"{len(ids)} blocks, {cells} cells, blocking {digest}",
        frame.to_unit(lay.points[stacked]), frame, source, settings=shared, layout=lay,
        drawn=np.flatnonzero(sides), ids=ids,
    )  # fmt: skip


def aligned(points: np.ndarray, ids: list, corners: list | None) -> list:
    """The layout's blocks' node ids (nj, ni) on the unique nodes ``points``, each turned
    (a quarter turn moves its corner 0 to the next corner) so that its corners, about their
    mean and scaled by their spread, lie nearest the reference's ``corners`` ((4, 2) a
    block, corner 0 first) taken the same way; as laid out where ``corners`` is None. A
    block's corner 0 is its least x + y, which a tie (a diagonal block edge) leaves to
    rounding; its shape is what a moved or resized member keeps."""
    if corners is None:
        return list(ids)
    out = []
    for k, ref in zip(ids, corners):
        turns = [np.rot90(k, t) for t in range(4)]
        far = [float(np.abs(_shape(points[_corner_ids(t)]) - _shape(ref)).sum()) for t in turns]
        out.append(turns[int(np.argmin(far))])
    return out


def _shape(corners: np.ndarray) -> np.ndarray:
    """``corners`` about their mean, scaled by their spread."""
    centred = corners - corners.mean(axis=0)
    return centred / max(float(np.linalg.norm(centred)), 1e-300)


def block_corners(member: Member) -> list[np.ndarray]:
    """The corners (4, 2) of each of ``member``'s blocks (family frame), corner 0 first."""
    unit = member.frame.to_unit(member.layout.points)
    return [unit[_corner_ids(k)] for k in member.ids]


def _corner_ids(ids: np.ndarray) -> np.ndarray:
    return np.array([ids[0, 0], ids[0, -1], ids[-1, -1], ids[-1, 0]])


def _side_mask(shape: tuple[int, int]) -> np.ndarray:
    """The nodes on the sides of a block of ``shape`` (nj, ni)."""
    mask = np.zeros(shape, dtype=bool)
    mask[0], mask[-1], mask[:, 0], mask[:, -1] = True, True, True, True
    return mask


def refuse_blocks_options(aux: Sequence, walls, gradings: Sequence, source: str) -> None:
    """Refuse, in one line, a multi-block member whose grid its options place otherwise than
    its blocking's solve: auxiliary lines, wall spacings or orthogonality, gradings."""
    asked = walls is not None and (walls.spacing or walls.orthogonal or walls.sides)
    if aux or gradings or asked:
        raise InputError(
            "a family model meshes multi-block domains without --aux, --spacing, "
            "--orthogonal or --grading in this build; drop them (or mesh without the model)",
            source,
        )
