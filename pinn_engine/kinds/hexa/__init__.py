"""Six-faced 3D domains (SPEC 11): ``run``, the geometry from a file or VTK data;
``mesh.mesh_surface``, the ``hexa`` package's face and volume grids, or the hexahedral block
kind (``problem``) from its ``start``."""
