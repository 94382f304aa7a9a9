"""SU2 native mesh (``.su2``), written by hand: a short, documented ASCII format.

2D only: quadrilaterals (VTK type 9) counter-clockwise, then one ``MARKER_TAG`` per patch
with its boundary lines (type 3) oriented with the domain on their left.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .block import Block
from .topology import quads, side_edges


def write(block: Block, path: Path) -> None:
    ni, nj = block.ni, block.nj
    cells = quads(ni, nj)
    with open(path, "w") as f:
        f.write("% SU2 mesh written by pinn-mesh\nNDIME= 2\n")
        f.write(f"NELEM= {len(cells)}\n")
        rows = np.column_stack([np.full(len(cells), 9), cells, np.arange(len(cells))])
        np.savetxt(f, rows, fmt="%d")
        f.write(f"NPOIN= {ni * nj}\n")
        xy = block.points.reshape(-1, 3)[:, :2]
        for k, (x, y) in enumerate(xy.tolist()):
            f.write(f"{x!r} {y!r} {k}\n")
        patches = block.patches()
        f.write(f"NMARK= {len(patches)}\n")
        for name, sides in patches.items():
            edges = np.vstack([side_edges(ni, nj, s) for s in sides])
            f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(edges)}\n")
            np.savetxt(f, np.column_stack([np.full(len(edges), 3), edges]), fmt="%d")
