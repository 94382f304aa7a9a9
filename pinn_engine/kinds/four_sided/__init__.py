"""The four-sided domain (SPEC 5): ``mesher.Mesher``, the estimator fitted once on a boundary
and its auxiliary lines and evaluated at any size; ``cache``, fitted meshers kept for re-use;
``problem``, the four-sided block its network trains, with ``mapping`` and ``model``."""

from pinn_engine.kinds.options import SHARED_2D

# The options a four-sided domain takes (its size, auxiliary lines, corners, a saved or
# family model)
OPTIONS = SHARED_2D | {"size", "lattice", "aux", "corners", "model", "save_model", "load_model"}
