"""Grids adapted to a solution (SPEC 14): the nodes of a finished 2D grid (four-sided, O/C
body or multi-block) moved so that cells are small where the monitor of a field is large,
its kind, counts, corners and patches kept; a guard on the worst cell that adapts less
where the strength asked would break it, and the grid kept only where it carries the field
better.

``grids.adapt_grids(grids, field, strength, held)`` does it on the blocks' node arrays; the
job (``job.adapted``) puts the result back into the run's VTK data. Only the field's reader
is imported here (a route reads the field before the run; SciPy comes with the solve)."""

from pinn_engine.adapt.field import Field, read_field, read_field_file

__all__ = ["Field", "read_field", "read_field_file"]
