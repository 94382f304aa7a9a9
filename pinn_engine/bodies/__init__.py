"""O- and C-grids around bodies (SPEC 9): airfoil input, the classical body grid, meshing a
body."""
