"""The domain kinds, one sub-package each: ``four_sided`` (SPEC 5), ``body`` (O- and C-grids,
SPEC 9), ``blocks`` (2D multi-block, SPEC 10), ``hexa`` (six-faced 3D, SPEC 11) and
``blocks3d`` (a blockMeshDict's blocks, SPEC 15). A kind's package holds what is its own: its
geometry adapters and run (what ``job``'s registry names), its pipeline (start, skip or
train, guard, report) and the problem its network trains. What kinds share is here too:
``outcome`` (what every run returns), ``single`` (the one geometry and run of a four-sided
domain and a body) and ``untrained`` (whether a network can win, and the one start -> skip
-> train -> guard sequence). The numerics they use stay in the layers below.
"""
