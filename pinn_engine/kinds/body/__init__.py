"""O- and C-grids round a body (SPEC 9): ``mesh.mesh_body``, the classical body grid, then
the body block kind (``problem``) where its network can win."""

from pinn_engine.kinds.options import SHARED_2D

# The options an O- or C-grid takes (its size, the body's topology, NACA code and far field,
# a family model)
OPTIONS = SHARED_2D | {"size", "lattice", "topology", "naca", "farfield", "model"}
