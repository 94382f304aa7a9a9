"""CGNS (``.cgns``) in its HDF5 layout, through ``h5py``.

The tree is small and fixed, so it is written node by node rather than through a binding
of the CGNS C library: one ``CGNSBase_t``,
one structured ``Zone_t`` with ``GridCoordinates`` (double), ``ZoneBC`` with one ``BC_t``
per side as a vertex ``PointRange`` (``FamilySpecified``, ``FamilyName`` = the patch name),
and one ``Family_t`` per patch (sides with one name share the family). Extruded grids are
3D zones with nk = 2 and the ends in the family ``frontAndBack``; a hexahedral grid (SPEC
11) is one 3D zone with a ``BC_t`` on each of its six sides.

HDF5 layout (CGNS "SIDS-to-HDF5" mapping): each node is a group with the attributes
``name``, ``label`` (33-byte strings), ``type`` (3 bytes: MT, C1, I4, R4, R8) and
``flags``; its value is the dataset " data", multi-dimensional arrays stored in Fortran
order (so an array of Fortran shape (ni, nj) is an HDF5 dataset of shape (nj, ni)).
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pinn_engine.errors import MissingExtraError
from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.joins import Join, joins
from pinn_engine.io.export.multiblock import Z_UP, Blocks
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.export.topology import box_range, index_range, layers
from pinn_engine.patchnames import FRONT_AND_BACK, TYPES

ROOT = Path(__file__).resolve().parents[3]  # the checkout (its .venv: the helper Python)

_TYPES = {np.dtype(np.int32): "I4", np.dtype(np.float32): "R4", np.dtype(np.float64): "R8"}


_H5PY: list = []  # [module or None]: h5py, once imported and found usable


def _h5py():
    """h5py, or None where it is missing or unusable. Inside Debian's ParaView a pip h5py
    finds ParaView's HDF5 already loaded and fails (version clash), hence the helper."""
    if not _H5PY:
        try:
            import h5py

            usable = h5py.version.hdf5_version_tuple == h5py.version.hdf5_built_version_tuple
        except Exception:  # ImportError, or a clash of HDF5 libraries at import
            h5py, usable = None, False
        _H5PY.append(h5py if usable else None)
    return _H5PY[0]


def _helper_python() -> str | None:
    """A Python with a working h5py to write CGNS for this one (ParaView's): the variable
    ``PINN_MESH_PYTHON``, else the checkout's ``.venv`` (``scripts/setup.sh``)."""
    given = os.environ.get("PINN_MESH_PYTHON")
    candidate = Path(given) if given else ROOT / ".venv" / "bin" / "python"
    if os.access(candidate, os.X_OK) and candidate.resolve() != Path(sys.executable).resolve():
        return str(candidate)
    return None


# the fix inside ParaView, whose Python takes no pip install (MissingExtraError.for_route)
PARAVIEW_FIX = (
    "the writer's helper Python: ParaView's HDF5 clashes with pip's h5py, so the writer "
    "runs the checkout's .venv Python: make it with bash scripts/setup.sh (or set "
    "PINN_MESH_PYTHON to a Python with h5py)"
)


def check() -> None:
    """Refuse (one line) where CGNS cannot be written: no h5py and no helper Python."""
    if _h5py() is None and _helper_python() is None:
        raise MissingExtraError("writing CGNS (h5py)", "cgns", "cgns", PARAVIEW_FIX)


def _write_in_helper(zones: list[Zone], types: dict[str, str], path: Path, extruded: bool) -> None:
    """Write the ``zones`` through the helper Python (:func:`_helper_python`): their arrays
    in an ``.npz`` beside ``path``, the rest (names, ranges, joins) as its JSON entry."""
    python = _helper_python()
    if python is None:
        check()
    data = path.with_name(path.name + ".npz")
    meta = {
        "types": types,
        "extruded": extruded,
        "zones": [
            {"name": z.name, "bcs": z.bcs, "joins": [dataclasses.astuple(j) for j in z.joins]}
            for z in zones
        ],
    }
    arrays = {f"xyz{k}": z.xyz for k, z in enumerate(zones)}
    try:
        np.savez(data, meta=np.array(json.dumps(meta)), **arrays)
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
        env["PYTHONPATH"] = str(ROOT)
        proc = subprocess.run(
            [python, "-m", "pinn_engine.io.export.cgns", str(data), str(path)],
            env=env,
            capture_output=True,
            text=True,
            timeout=3600,
        )
    finally:
        data.unlink(missing_ok=True)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["no message"])[-1]
        raise OSError(f"the CGNS helper ({python}) failed: {last}")


def _ranges(rng) -> tuple:
    """A point range read back from JSON (lists) as the tuples it was."""
    return tuple(tuple(corner) for corner in rng)


def _main() -> None:
    """``python -m pinn_engine.io.export.cgns DATA.npz OUT.cgns`` (the helper's side)."""
    data = np.load(sys.argv[1])
    meta = json.loads(str(data["meta"]))
    zones = [
        Zone(
            z["name"],
            data[f"xyz{k}"],
            [(label, name, _ranges(rng)) for label, name, rng in z["bcs"]],
            [Join(n, d, _ranges(a), _ranges(b), tuple(t)) for n, d, a, b, t in z["joins"]],
        )
        for k, z in enumerate(meta["zones"])
    ]
    write_zones(zones, meta["types"], Path(sys.argv[2]), meta["extruded"])


def _attr(node, key: str, text: str, size: int) -> None:
    node.attrs.create(key, np.array(text.encode("ascii"), dtype=f"S{size}"))


def _node(parent, name: str, label: str, value=None):
    """A CGNS node: ``value`` a string (C1) or an array (stored in Fortran order)."""
    group = parent.create_group(name, track_order=True)
    _attr(group, "name", name, 33)
    _attr(group, "label", label, 33)
    group.attrs.create("flags", np.array([1], dtype=np.int32))
    if value is None:
        _attr(group, "type", "MT", 3)
        return group
    if isinstance(value, str):
        kind, data = "C1", np.frombuffer(value.encode("ascii"), dtype=np.int8)
    else:
        data = np.asarray(value)
        kind, data = _TYPES[data.dtype], data.T  # Fortran order: reverse the axes
    _attr(group, "type", kind, 3)
    group.create_dataset(" data", data=np.ascontiguousarray(data))
    return group


@dataclass(frozen=True)
class Zone:
    """One structured zone: ``xyz`` (nk, nj, ni, 3), its boundary conditions ``bcs`` as
    (BC name, patch name, 1-based point range: 2D (i, j), or (i, j, k) in a hexahedral
    grid) and its 1-to-1 ``joins``."""

    name: str
    xyz: np.ndarray
    bcs: list[tuple[str, str, tuple[tuple[int, int], tuple[int, int]]]]
    joins: list[Join]


def _bc_name(name: str, side: str, shared: bool) -> str:
    return f"{name[: 32 - len(side) - 1]}_{side}" if shared else name


def _deep(rng, extruded: bool):
    """A 2D range through both layers of an extrusion (as is otherwise)."""
    lo, hi = rng
    return ((*lo, 1), (*hi, 2)) if extruded else rng


def _side_bcs(ranges: dict[str, list]) -> list:
    """BCs (BC name, patch name, range) of patch name -> [(side, range)]: a patch of several
    sides has a BC per side, named after both."""
    return [
        (_bc_name(name, side, len(parts) > 1), name, rng)
        for name, parts in ranges.items()
        for side, rng in parts
    ]


def write(block: Block, path: Path) -> None:
    """A 2D grid (extruded where asked) as one zone, a ``BC_t`` per side; an O- or C-grid
    with the joins of its seam or wake cut."""
    ni, nj = block.ni, block.nj
    if block.topology:
        ranges = _body_ranges(block)
        joins = _body_joins(block)
    else:
        joins = []
        ranges = {
            name: [(side, index_range(ni, nj, side)) for side in sides]
            for name, sides in block.patches().items()
        }
    types = {name: block.patch_type(name) for name in ranges}
    write_zones([Zone("Zone", block.layers(), _side_bcs(ranges), joins)], types, path)


def write_box(box: Box, path: Path) -> None:
    """A hexahedral grid as one 3D zone, a ``BC_t`` per side (SPEC 11)."""
    shape = box.shape
    ranges = {
        name: [(side, box_range(*shape, side)) for side in sides]
        for name, sides in box.patches().items()
    }
    types = {name: box.patch_type(name) for name in ranges}
    write_zones([Zone("Zone", box.xyz, _side_bcs(ranges), [])], types, path, extruded=False)


def write_zones(
    zones: list[Zone], types: dict[str, str], path: Path, extruded: bool = True
) -> None:
    """A CGNS file of structured ``zones`` (all 2D, or all 3D: extruded 2D grids, nk = 2,
    the ends in the family ``frontAndBack``, unless not ``extruded``: hexahedral grids),
    a ``Family_t`` per patch of ``types`` (name -> type)."""
    h5py = _h5py()
    if h5py is None:  # ParaView's Python: the helper Python writes them
        _write_in_helper(zones, types, path, extruded)
        return
    three_d = zones[0].xyz.shape[0] > 1
    extruded = three_d and extruded
    dim = 3 if three_d else 2
    with h5py.File(path, "w", track_order=True) as f:
        _attr(f, "name", "HDF5 MotherNode", 33)
        _attr(f, "label", "Root Node of HDF5 File", 33)
        _attr(f, "type", "MT", 3)
        order = "LITTLE" if sys.byteorder == "little" else "BIG"
        f.create_dataset(" format", data=np.frombuffer(f"IEEE_{order}_32".encode(), np.int8))
        version = f"HDF5 Version {'.'.join(map(str, h5py.h5.get_libversion()))}"
        f.create_dataset(
            " hdf5version",
            data=np.frombuffer(version.encode("ascii").ljust(33, b"\0"), dtype=np.int8),
        )
        _node(f, "CGNSLibraryVersion", "CGNSLibraryVersion_t", np.array([3.4], np.float32))
        base = _node(f, "Base", "CGNSBase_t", np.array([dim, dim], np.int32))
        for zone in zones:
            _zone(base, zone, three_d, extruded)
        families = dict(types, **({FRONT_AND_BACK: "patch"} if extruded else {}))
        for name, kind in families.items():
            family = _node(base, name, "Family_t")
            _node(family, "FamilyBC", "FamilyBC_t", TYPES[kind][1])


def _zone(base, zone: Zone, three_d: bool, extruded: bool) -> None:
    """A ``Zone_t`` with its coordinates, ``ZoneBC`` and ``ZoneGridConnectivity``."""
    xyz = zone.xyz
    nk, nj, ni = xyz.shape[:3]
    dims = [ni, nj, nk] if three_d else [ni, nj]
    size = np.array([dims, [n - 1 for n in dims], [0] * len(dims)], np.int32).T  # (dim, 3)
    node = _node(base, zone.name, "Zone_t", size)
    _node(node, "ZoneType", "ZoneType_t", "Structured")
    coords = _node(node, "GridCoordinates", "GridCoordinates_t")
    for axis, key in enumerate("XYZ"[: len(dims)]):
        values = xyz[..., axis] if three_d else xyz[0, ..., axis]  # C (k, j, i)
        # Fortran (i, j, k)
        _node(coords, f"Coordinate{key}", "DataArray_t", np.ascontiguousarray(values.T, np.float64))
    zone_bc = _node(node, "ZoneBC", "ZoneBC_t")
    bcs = [(label, name, _deep(rng, extruded)) for label, name, rng in zone.bcs]
    if extruded:  # the ends
        bcs += [
            (f"{FRONT_AND_BACK}_back", FRONT_AND_BACK, ((1, 1, 1), (ni, nj, 1))),
            (f"{FRONT_AND_BACK}_front", FRONT_AND_BACK, ((1, 1, 2), (ni, nj, 2))),
        ]
    for label, name, (lo, hi) in bcs:
        bc = _node(zone_bc, label, "BC_t", "FamilySpecified")
        _node(bc, "PointRange", "IndexRange_t", np.array([lo, hi], np.int32).T)
        _node(bc, "FamilyName", "FamilyName_t", name)
    if not zone.joins:
        return
    grid_conn = _node(node, "ZoneGridConnectivity", "ZoneGridConnectivity_t")
    for join in zone.joins:
        transform = list(join.transform) + ([3] if extruded else [])
        conn = _node(grid_conn, join.name, "GridConnectivity1to1_t", join.donor)
        _node(conn, "Transform", '"int[IndexDimension]"', np.array(transform, np.int32))
        _node(conn, "PointRange", "IndexRange_t", np.array(_deep(join.here, extruded), np.int32).T)
        there = np.array(_deep(join.there, extruded), np.int32).T
        _node(conn, "PointRangeDonor", "IndexRange_t", there)


def _body_ranges(block: Block) -> dict[str, list]:
    """BC point ranges of an O- or C-grid: the wall (the C-grid's body part of j = 1), the
    far field (j = nj) and the C-grid's outflow columns; the seam and cut have none."""
    ni, nj, nw = block.ni, block.nj, block.n_wake
    bottom, right, top, left = block.names
    if block.topology == "o":
        parts = [(bottom, "wall", ((1, 1), (ni, 1))), (top, "farfield", ((1, nj), (ni, nj)))]
    else:
        parts = [
            (bottom, "wall", ((nw + 1, 1), (ni - nw, 1))),
            (right, "right", ((ni, 1), (ni, nj))),
            (top, "farfield", ((1, nj), (ni, nj))),
            (left, "left", ((1, 1), (1, nj))),
        ]
    out: dict[str, list] = {}
    for name, side, rng in parts:
        out.setdefault(name, []).append((side, rng))
    return out


def _body_joins(block: Block) -> list[Join]:
    """The seam (O) or the wake cut (C) as two joins of the zone with itself (one from each
    side, as CGNS asks for every 1-to-1 interface)."""
    ni, nj, nw = block.ni, block.nj, block.n_wake
    if block.topology == "o":  # column i = 1 is column i = ni; i and j run alike
        a, b, transform = ((1, 1), (1, nj)), ((ni, 1), (ni, nj)), (1, 2)
    else:  # node (i, 1) is node (ni + 1 - i, 1): i and j run opposite
        a, b, transform = ((1, 1), (nw + 1, 1)), ((ni, 1), (ni - nw, 1)), (-1, -2)
    name = "seam" if block.topology == "o" else "wake_cut"
    return [Join(f"{name}_a", "Zone", a, b, transform), Join(f"{name}_b", "Zone", b, a, transform)]


def zones(blocks: Blocks, thickness: float | None) -> list[Zone]:
    """A CGNS zone a block (named ``block0``, ...): its BCs and its joins."""
    out = []
    for k, (pts, pieces) in enumerate(zip(blocks.points, blocks.pieces)):
        count = {}
        for p in pieces:
            count[p.name] = count.get(p.name, 0) + 1
        bcs = []
        for n, p in enumerate(pieces):
            i0, j0, i1, j1 = p.nodes
            label = f"{p.name[:28]}_{n}" if count[p.name] > 1 else p.name
            bcs.append((label, p.name, ((i0 + 1, j0 + 1), (i1 + 1, j1 + 1))))
        xyz = layers(pts, thickness, Z_UP)
        out.append(Zone(f"block{k}", xyz, bcs, joins(blocks.points, k)))
    return out


def write_blocks(blocks: Blocks, path: Path, extrude: float | None) -> None:
    """A multi-block grid (SPEC 10): a zone a block with its joins, a ``BC_t`` a piece."""
    write_zones(zones(blocks, extrude), blocks.types(), path)


register(
    Format(
        "cgns",
        ".cgns",
        "CGNS/HDF5 with boundary patches",
        True,
        name="CGNS",
        block=write,
        box=write_box,
        blocks=write_blocks,
        blocks_extrude=True,
        check=check,
        paraview=("cgns", "PINNMeshCGNSWriter", "PINN Mesh CGNS"),
    )
)


if __name__ == "__main__":
    _main()
