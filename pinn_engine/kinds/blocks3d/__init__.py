"""A blockMeshDict's blocks (SPEC 15): ``run``, the dictionary read from a file or text,
meshed by the ``blocks3d`` package and written as CGNS zones or unstructured hexahedra."""
