"""Reading inputs, VTK grids, the solver formats."""
