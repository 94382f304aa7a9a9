"""The ways in: command line, VTK algorithms, pyvista accessor, pictures, the cache of fitted
networks."""
