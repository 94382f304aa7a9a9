"""The grids a network starts from: the elliptic warm start, the wall-orthogonal start, the
quality objective's start (node optimisation before training)."""
