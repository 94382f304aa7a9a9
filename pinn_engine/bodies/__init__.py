"""Bodies (SPEC 9): airfoil input (Selig, Lednicer, NACA), far fields, and the classical O- and
C-grid (layout, marching reference grid, TFI and elliptic sweeps with controls)."""
