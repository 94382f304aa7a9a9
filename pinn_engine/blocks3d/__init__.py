"""Multi-block 3D domains from an OpenFOAM blockMeshDict (SPEC 15)."""
