"""The names every route shares (methods, presets, objectives, topologies, a six-faced
domain's patches), the limits on a grid's size and the measured defaults."""

from __future__ import annotations

METHODS = ("pinn", "mgnet", "tfi", "elliptic")
NEURAL = ("pinn", "mgnet")  # the methods that train a network
PRESETS = ("default", "paper")
# SPEC 7, --objective (pinn): best (the default: the quality objective's grid where it applies,
# the Winslow equations' elsewhere), winslow, quality
OBJECTIVES = ("best", "winslow", "quality")
TOPOLOGIES = ("none", "o", "c")  # SPEC 9: a four-sided domain, an O-grid or a C-grid
BODY_METHODS = ("pinn", "tfi", "elliptic")  # the methods of O- and C-grids
MULTIBLOCK_METHODS = ("tfi", "elliptic", "pinn")  # SPEC 10's methods in this build
BLOCKS_METHOD = "pinn"  # multi-block's default method (SPEC 10), on every route
AUTO_BLOCKS = "auto"  # block edges named so are proposed from the boundary (SPEC 13)
HEXA_METHODS = ("pinn", "tfi", "elliptic")  # SPEC 11's methods, in the filter's order
DICTIONARY_METHODS = ("pinn", "elliptic", "tfi")  # SPEC 15's methods, the default first
HEXA_METHOD = "pinn"  # SPEC 11's default (kinds/hexa/problem.py; docs/hexa.md has its figures)
BOX_SIDES = ("imin", "imax", "jmin", "jmax", "kmin", "kmax")  # a six-faced domain's patches
FACE_ANGLE = 40.0  # degrees between neighbouring triangles' normals that end a face (SPEC 11)
OPPOSITE_NODES = 4  # two orthogonal opposite patches each need a first layer of their own
# A six-faced domain's L-BFGS iterations: its residual falls from the Winslow start by a
# quarter in 20 and a third in 120 at nearly the same grid (docs/hexa.md), each costing
# about 40 ms at 21^3
HEXA_LBFGS_ITERATIONS = 20
# Grid sizes accepted on every route (command line, filter and panel, pyvista, Mesher)
MAX_SIDE_NODES = 20_000
MAX_NODES = 4_000_000  # about 1.5 GB of memory while meshing and writing
# The warm start's elliptic solve grows faster than linearly with the nodes (measured on the
# V notch, 2 busy cores: 1 s at 161 x 81, 16 s at 321 x 161, 106 s at 641 x 321); above this
# many nodes it runs on a coarser lattice of the same shape, and the network is evaluated finer
# (starts/warmstart.py). The default takes the quality objective only up to it: the spline of
# an optimised coarser lattice can fold cells of the finer grid (a bump at 641 x 321: 54).
MAX_LATTICE_NODES = 161 * 81
DEFAULT_SIZE = (41, 21)  # nodes along xi and eta of a four-sided grid or a body (SPEC 5)
HEXA_SIZE = (21, 21, 21)  # SPEC 11's default nodes along i, j and k
MIN_HEXA_NODES = 3  # fewer nodes along a direction leave no interior to solve for
# Training's wall-clock limit in seconds, after which the best state so far is kept
NO_TIME_LIMIT = 0.0  # command line, pyvista, VTK: a limit would tie the grid to machine speed
# SPEC 14's monitor strength beta with --adapt (docs/adaptation.md: the analytic fields'
# interpolation error on the tuning shapes, benchmarks/adapt.py)
ADAPT_STRENGTH = 20.0
PANEL_TIME_LIMIT = 60.0  # ParaView 5.11 freezes while a filter runs; the paper preset (~33 s) fits


def grid_size_problem(ni: int, nj: int) -> str | None:
    """What is wrong with a grid of ``ni`` x ``nj`` nodes, or None; each route prefixes its
    own name for the size (``--size``, ``size=``, Grid Size)."""
    if min(ni, nj) < 2 or max(ni, nj) > MAX_SIDE_NODES or ni * nj > MAX_NODES:
        return (
            f"each side must have 2 to {MAX_SIDE_NODES:,} nodes and the grid at most "
            f"{MAX_NODES:,} nodes"
        )
    return None


def size_problem(size: tuple[int, ...]) -> str | None:
    """What is wrong with a grid size of two node counts (a 2D domain) or more (a six-faced
    3D domain's, :func:`hexa_size_problem`), or None; each route prefixes its own name."""
    return grid_size_problem(*size) if len(size) == 2 else hexa_size_problem(size)


def hexa_size_problem(size: tuple[int, ...]) -> str | None:
    """What is wrong with a six-faced 3D domain's grid size, or None."""
    if len(size) != len(HEXA_SIZE):
        return "a six-faced surface takes three sizes (nodes along i, j and k)"
    if min(size) < MIN_HEXA_NODES:
        return f"each needs at least {MIN_HEXA_NODES} nodes"
    return None
