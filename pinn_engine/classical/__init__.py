"""The classical grid methods: transfinite interpolation, the elliptic (Winslow) solver, node
spacing."""
