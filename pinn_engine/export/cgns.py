"""CGNS (``.cgns``) in its HDF5 layout, through ``h5py``.

The tree is small and fixed, so it is written node by node rather than through the CGNS
library (whose Python bindings, pyCGNS, are not on PyPI as wheels): one ``CGNSBase_t``,
one structured ``Zone_t`` with ``GridCoordinates`` (double), ``ZoneBC`` with one ``BC_t``
per side as a vertex ``PointRange`` (``FamilySpecified``, ``FamilyName`` = the patch name),
and one ``Family_t`` per patch (sides with one name share the family). Extruded grids are
3D zones with nk = 2 and the ends in the family ``frontAndBack``.

HDF5 layout (CGNS "SIDS-to-HDF5" mapping): each node is a group with the attributes
``name``, ``label`` (33-byte strings), ``type`` (3 bytes: MT, C1, I4, R4, R8) and
``flags``; its value is the dataset " data", multi-dimensional arrays stored in Fortran
order (so an array of Fortran shape (ni, nj) is an HDF5 dataset of shape (nj, ni)).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .block import Block
from .patches import FRONT_AND_BACK
from .topology import index_range

_TYPES = {np.dtype(np.int32): "I4", np.dtype(np.float32): "R4", np.dtype(np.float64): "R8"}


def _h5py():
    try:
        import h5py
    except ImportError:
        from ..errors import InputError

        raise InputError("writing CGNS needs the h5py package, which this Python lacks; "
                         "{h5py}", "cgns") from None
    return h5py


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


def _bc_name(name: str, side: str, shared: bool) -> str:
    return f"{name[:32 - len(side) - 1]}_{side}" if shared else name


def write(block: Block, path: Path) -> None:
    h5py = _h5py()
    xyz = block.layers()
    nk, nj, ni = xyz.shape[:3]
    three_d = nk > 1
    dims = [ni, nj, nk] if three_d else [ni, nj]
    with h5py.File(path, "w", track_order=True) as f:
        _attr(f, "name", "HDF5 MotherNode", 33)
        _attr(f, "label", "Root Node of HDF5 File", 33)
        _attr(f, "type", "MT", 3)
        order = "LITTLE" if sys.byteorder == "little" else "BIG"
        f.create_dataset(" format", data=np.frombuffer(f"IEEE_{order}_32".encode(), np.int8))
        version = f"HDF5 Version {'.'.join(map(str, h5py.h5.get_libversion()))}"
        f.create_dataset(" hdf5version", data=np.frombuffer(
            version.encode("ascii").ljust(33, b"\0"), dtype=np.int8))
        _node(f, "CGNSLibraryVersion", "CGNSLibraryVersion_t", np.array([3.4], np.float32))
        dim = 3 if three_d else 2
        base = _node(f, "Base", "CGNSBase_t", np.array([dim, dim], np.int32))
        size = np.array([dims, [n - 1 for n in dims], [0] * dim], np.int32).T  # (dim, 3)
        zone = _node(base, "Zone", "Zone_t", size)
        _node(zone, "ZoneType", "ZoneType_t", "Structured")
        coords = _node(zone, "GridCoordinates", "GridCoordinates_t")
        for axis, key in enumerate("XYZ"[:dim]):
            values = xyz[..., axis] if three_d else xyz[0, ..., axis]  # C (k, j, i)
            _node(coords, f"Coordinate{key}", "DataArray_t",
                  np.ascontiguousarray(values.T, dtype=np.float64))  # Fortran (i, j, k)
        zone_bc = _node(zone, "ZoneBC", "ZoneBC_t")
        patches = block.patches()
        ranges = {name: [(side, index_range(ni, nj, side)) for side in sides]
                  for name, sides in patches.items()}
        if three_d:
            for name in ranges:  # the sides reach through both layers
                ranges[name] = [(s, ((*lo, 1), (*hi, 2))) for s, (lo, hi) in ranges[name]]
            ranges.setdefault(FRONT_AND_BACK, []).extend([
                ("back", ((1, 1, 1), (ni, nj, 1))), ("front", ((1, 1, 2), (ni, nj, 2)))])
        for name, parts in ranges.items():
            for side, (lo, hi) in parts:
                bc = _node(zone_bc, _bc_name(name, side, len(parts) > 1), "BC_t",
                           "FamilySpecified")
                _node(bc, "PointRange", "IndexRange_t", np.array([lo, hi], np.int32).T)
                _node(bc, "FamilyName", "FamilyName_t", name)
        for name in ranges:
            family = _node(base, name, "Family_t")
            _node(family, "FamilyBC", "FamilyBC_t", "BCTypeUserDefined")
