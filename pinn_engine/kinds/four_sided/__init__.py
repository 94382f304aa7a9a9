"""The four-sided domain (SPEC 5): ``mesher.Mesher``, the estimator fitted once on a boundary
and its auxiliary lines and evaluated at any size; ``cache``, fitted meshers kept for re-use;
``problem``, the four-sided block its network trains, with ``mapping`` and ``model``."""
