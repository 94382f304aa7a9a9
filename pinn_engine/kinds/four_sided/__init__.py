"""The four-sided domain (SPEC 5): ``mesher.Mesher``, the estimator fitted once on a boundary
and its auxiliary lines and evaluated at any size."""
