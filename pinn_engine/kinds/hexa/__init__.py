"""Six-faced 3D domains (SPEC 11): ``run``, the geometry from a file or VTK data;
``mesh.mesh_surface``, the ``hexa`` package's face and volume grids, or the hexahedral block
kind (``problem``) from its ``start``."""

# The options a six-faced 3D domain takes (spacing and orthogonal on its patches, its faces
# found at face_angle)
OPTIONS = frozenset(
    {"method", "size", "patches", "spacing", "orthogonal", "face_angle", "save_model", "load_model"}
)
