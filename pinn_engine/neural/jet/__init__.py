"""The networks' derivative jets: the math and torch layers (layers.py), the whole network in
C++ (kernels.cpp, built and loaded by native.py)."""

from pinn_engine.neural.jet.layers import (
    ETA,
    ETAETA,
    FIRST,
    SECOND,
    XI,
    XIETA,
    XIXI,
    V,
    input_jet,
    jet_product,
)

__all__ = [
    "ETA",
    "ETAETA",
    "FIRST",
    "SECOND",
    "V",
    "XI",
    "XIETA",
    "XIXI",
    "input_jet",
    "jet_product",
]
