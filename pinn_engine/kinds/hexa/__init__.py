"""Six-faced 3D domains (SPEC 11): ``mesh.mesh_surface``, the ``hexa`` package's face and
volume grids, or the hexahedral block kind."""
