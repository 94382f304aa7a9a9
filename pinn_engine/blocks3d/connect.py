"""A meshed dictionary's blocks as structured zones see them (CGNS, SPEC 15): each block's
boundary faces by patch, and each face two blocks share as a 1-to-1 join from both sides,
with the signed donor axis of each of its own axes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.blocks3d.placement import HEX_FACES, Placement, block_faces, face_slice

Range = tuple[tuple[int, int, int], tuple[int, int, int]]  # 1-based (i, j, k) begin and end


@dataclass
class Join:
    """Block ``block``'s face ``here`` meeting block ``donor``'s ``there`` (its begin the
    node at our begin, its end at our end); ``transform[m]``: the donor axis (1-based,
    signed) our axis m runs along."""

    block: int
    donor: int
    here: Range
    there: Range
    transform: tuple[int, int, int]


def face_range(shape: tuple[int, ...], axis: int, end: int) -> Range:
    """The 1-based point range of a block face of a block of ``shape`` nodes."""
    lo = [1, 1, 1]
    hi = list(shape)
    lo[axis] = hi[axis] = shape[axis] if end else 1
    return tuple(lo), tuple(hi)


def boundary_faces(place: Placement) -> list[list[tuple[str, Range]]]:
    """Per block, (patch name, point range) of each of its faces on the boundary."""
    owner: dict[tuple[int, ...], str] = {}
    for name, _, faces in place.patches:
        for quad in faces:
            owner[tuple(sorted(quad.tolist()))] = name
    out = []
    for b, ids in enumerate(place.ids):
        faces = []
        for axis, end in HEX_FACES:
            if (b, axis, end) in place.interfaces:
                continue
            first = tuple(sorted(block_faces(ids, axis, end)[0].tolist()))
            faces.append((owner[first], face_range(ids.shape, axis, end)))
        out.append(faces)
    return out


def joins(place: Placement) -> list[Join]:
    """Every shared face as a join from each of its two blocks."""
    out = []
    for b, ids in enumerate(place.ids):
        for axis, end in HEX_FACES:
            if (b, axis, end) not in place.interfaces:
                continue
            face = ids[face_slice(axis, end)]
            for c, other in enumerate(place.ids):
                if c == b:
                    continue
                for oaxis, oend in HEX_FACES:
                    if (c, oaxis, oend) not in place.interfaces:
                        continue
                    theirs = other[face_slice(oaxis, oend)]
                    if set(theirs[[0, 0, -1, -1], [0, -1, 0, -1]].tolist()) == set(
                        face[[0, 0, -1, -1], [0, -1, 0, -1]].tolist()
                    ):
                        out.append(_join(b, ids, axis, end, c, other, oaxis, oend))
    return out


def _join(b, ids, axis, end, c, other, oaxis, oend) -> Join:
    sl = face_slice(oaxis, oend)
    index = np.indices(other.shape)[(slice(None), *sl)].reshape(3, -1).T
    where = {int(n): tuple(int(v) for v in idx) for n, idx in zip(other[sl].ravel(), index)}
    here = face_range(ids.shape, axis, end)
    begin = tuple(v - 1 for v in here[0])
    finish = tuple(v - 1 for v in here[1])
    there_begin, there_end = where[int(ids[begin])], where[int(ids[finish])]
    transform = [0, 0, 0]
    for m in range(3):
        if m == axis:  # across the face: into us is out of the donor
            transform[m] = (oaxis + 1) * (1 if end != oend else -1)
            continue
        step = list(begin)
        step[m] += 1
        moved = np.subtract(where[int(ids[tuple(step)])], there_begin)
        k = int(np.flatnonzero(moved)[0])
        transform[m] = (k + 1) * int(np.sign(moved[k]))
    there = (tuple(v + 1 for v in there_begin), tuple(v + 1 for v in there_end))
    return Join(b, c, here, there, tuple(transform))
