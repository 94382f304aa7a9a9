"""Multi-block 2D domains (SPEC 10): ``run``, the geometry from files or VTK data and the
run of the ``multiblock`` package's grid, and ``problem``, the four-sided problem trained on
each block."""
