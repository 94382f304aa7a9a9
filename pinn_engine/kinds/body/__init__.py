"""O- and C-grids round a body (SPEC 9): ``mesh.mesh_body``, the classical body grid, then
the body block kind (``problem``) where its network can win."""
