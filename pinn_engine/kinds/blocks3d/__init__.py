"""A blockMeshDict's blocks (SPEC 15): ``run``, the dictionary read from a file or text,
meshed by the ``blocks3d`` package and written as CGNS zones or unstructured hexahedra."""

# The options a blockMeshDict takes: its blocks, counts, gradings and patches are the
# dictionary's
OPTIONS = frozenset({"method", "interfaces"})
