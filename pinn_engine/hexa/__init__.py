"""Hexahedral grids of six-faced 3D domains (SPEC 11): surface topology, face grids on the
surface, volume grids by 3D TFI or 3D Winslow, and their quality."""
