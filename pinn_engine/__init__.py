"""pinn-mesh: structured quadrilateral meshes from a physics-informed neural network."""

__version__ = "0.1.0"
