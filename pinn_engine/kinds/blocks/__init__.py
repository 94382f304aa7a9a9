"""Multi-block 2D domains (SPEC 10): ``run``, the geometry from files or VTK data and the
run of the ``multiblock`` package's grid, and ``problem``, the four-sided problem trained on
each block."""

from pinn_engine.kinds.options import SHARED_2D

# The options a multi-block domain takes (its block edges, cell counts and gradings along
# chains, the cells' size, its interfaces, auxiliary lines inside blocks, a family model)
OPTIONS = SHARED_2D | {
    "blocks",
    "save_blocks",
    "aux",
    "cells",
    "grading",
    "cell_size",
    "interfaces",
    "model",
}
