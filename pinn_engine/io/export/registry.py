"""The export formats (SPEC 8), each registered once by its own module, as meshio's are.

A format module calls :func:`register` with its :class:`Format` when it is imported;
``registered.py`` imports every format module, on the first use of the package's
``io.export.FORMATS`` (``formats()``), which then holds them all: the writers, the command
line's ``--format``, the multi-block writer and the ParaView writers read it instead of
tables of their own. This module's own ``FORMATS`` holds only the formats imported so far.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

# A writer of one kind of grid: the grid (a vtkStructuredGrid with its patch arrays, a 2D
# Block, a hexahedral Box, or a multi-block Blocks and its extrusion) and the path
Writer = Callable[..., Any]


@dataclass(frozen=True)
class Format:
    """A solver format: its ``key`` (``--format``), file ``suffix`` ("" for a folder),
    ``description`` (for messages and ParaView), whether it ``extrudes`` a 2D grid, and its
    writers, None where it does not take that kind of grid.

    ``grid(vtk_grid, path)`` writes the VTK grid itself, atomically. The others write to a
    temporary file beside the target (renamed over it when complete), or for a folder
    format into a new ``constant/polyMesh``: ``block(block, path)`` a 2D grid,
    ``box(box, path)`` a hexahedral grid, ``blocks(blocks, path, extrude)`` a multi-block
    grid (extruded only where ``blocks_extrude``). ``solid``: always written in 3D (a 2D
    grid gets one cell of its mean edge length unless extruded). ``check()`` refuses, in
    one line and before any meshing, where this Python cannot write it. ``paraview``: the
    ParaView writer's (extension, proxy name, file type), if it has one.
    """

    key: str
    suffix: str
    description: str
    extrudes: bool
    name: str  # how messages name it: PLOT3D, CGNS, ...
    grid: Writer | None = None
    block: Writer | None = None
    box: Writer | None = None
    blocks: Writer | None = None
    blocks_extrude: bool = False
    solid: bool = False
    check: Callable[[], None] | None = None
    paraview: tuple[str, str, str] | None = None


FORMATS: dict[str, Format] = {}


def register(fmt: Format) -> Format:
    """Add ``fmt`` to ``FORMATS`` (a module imported again, as ``python -m``, replaces its
    own); a suffix that another key has is a programming error."""
    taken = [f.key for f in FORMATS.values() if f.key != fmt.key and fmt.suffix == f.suffix != ""]
    if taken:
        raise ValueError(f"export format {fmt.key!r} clashes with {taken[0]!r}")
    FORMATS[fmt.key] = fmt
    return fmt
