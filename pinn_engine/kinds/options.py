"""The options the domain kinds share, from which each kind's package declares its own
``OPTIONS`` (the one place that says which option applies to which kind; ``job.OPTIONS``
gathers them, the routes word them).

An option is named by its one name: a setting of ``settings.Settings``, or an input a route
takes by that name (``aux``, ``blocks``, ``patches`` ...)."""

from __future__ import annotations

from pinn_engine.settings import CORE_CONSTRAINTS

# The network, its training and the elliptic start (the core's settings less the method and
# the adaptation's strength, which each kind that takes one declares itself): every 2D kind
# trains its blocks' pinn
TRAINING = frozenset(CORE_CONSTRAINTS) - {"method", "adapt_strength"} | {"device"}
# A 2D grid adapted to a field (SPEC 14) and written extruded, drawn, or refused folded
GRID_2D = frozenset({"adapt", "adapt_strength", "extrude", "png", "fail_on_folded"})
# What every 2D kind takes: the method, patch names, spacing and orthogonal places (sides,
# patches), and the above
SHARED_2D = frozenset({"method", "patches", "spacing", "orthogonal"}) | TRAINING | GRID_2D
