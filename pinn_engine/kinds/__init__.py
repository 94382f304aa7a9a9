"""The domain kinds, one sub-package each: ``four_sided`` (SPEC 5), ``body`` (O- and C-grids,
SPEC 9), ``hexa`` (six-faced 3D, SPEC 11). A kind's package holds what is its own: its
pipeline (start, skip or train, guard, report) and the block kind its network trains;
``job`` finds each kind in its registry, the numerics they share stay in the layers below.
"""
