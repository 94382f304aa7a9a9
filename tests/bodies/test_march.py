"""The body grid's march compiled (bodies/march.cpp) gives the NumPy loop's reference grids
bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine.bodies import bodygrid, marching
from pinn_engine.bodies.airfoil import body_from_points, circle, naca4
from pinn_engine.neural.jet import native


@pytest.fixture(scope="module")
def compiled(tmp_path_factory):
    """The install's library, else one built here (skipped without a compiler)."""
    lib = marching.library()
    if lib is None:
        compiler = native._compiler()
        if compiler is None:
            pytest.skip("no C++ compiler to build the march with")
        folder = tmp_path_factory.mktemp("march")
        lib = marching.load(marching.build_packaged(folder, compiler, native._compile))
    return lib


def _ring(n: int = 96) -> np.ndarray:
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([np.cos(t), 0.4 * np.sin(t)])


BODIES = {  # a blunt section (a C-grid's base corners), a sharp one, a round edge
    "naca 2412 blunt": naca4("2412", points=81, te="blunt"),
    "naca 4415 sharp": naca4("4415", points=81),
    "ellipse": _ring(),
}


@pytest.mark.parametrize("name", BODIES)
@pytest.mark.parametrize("topology", ["o", "c"])
def test_the_compiled_march_gives_the_numpy_grid_bit_for_bit(compiled, monkeypatch, name, topology):
    body = body_from_points(BODIES[name], name)
    far = circle(body, 15.0)
    grids = []
    for lib in (compiled, None):
        monkeypatch.setattr(marching, "library", lambda lib=lib: lib)
        lay = bodygrid.layout(body, far, topology, 41, 17)
        grids.append(lay.reference)
    assert grids[0].tobytes() == grids[1].tobytes()
    assert np.ptp(grids[0][-1], axis=0).min() > 20.0  # marched out to the far field


def test_the_install_goes_on_without_a_compiler_or_a_build(tmp_path, capsys):
    assert marching.build_packaged(tmp_path, None, native._compile) is None

    def broken(*args):
        raise native.NativeBuildError("`c++ ...` failed")

    assert marching.build_packaged(tmp_path, "c++", broken) is None
    assert "NumPy" in capsys.readouterr().out
    assert not list(tmp_path.iterdir())
