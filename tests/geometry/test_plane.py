"""Boundaries in any plane: meshed in their own plane, handed back in the user's 3D frame."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.geometry.plane import Plane
from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.routes.cli import main
from pinn_engine.routes.pyvista_accessor import pinn_mesh
from pinn_engine.settings import make_settings

SHORT = {"adam_epochs": 0, "lbfgs_iterations": 5}


def rotation(a: float, b: float) -> np.ndarray:
    """A rotation about z by ``a`` then about x by ``b``: a plane that is no coordinate plane."""
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    return rx @ rz


def moved(poly: pv.PolyData, matrix: np.ndarray, shift) -> pv.PolyData:
    out = poly.copy()
    out.points = poly.points @ matrix.T + np.asarray(shift, dtype=float)
    return out


@pytest.fixture
def fig2():
    return pv.read(EXAMPLES / "fig2.vtp"), pv.read(EXAMPLES / "fig2_aux.vtp")


def test_tilted_plane_gives_the_flat_grid_moved(fig2):
    boundary, aux = fig2
    flat = pinn_mesh(boundary, aux=aux, size=(21, 11), method="elliptic")
    matrix, shift = rotation(0.4, 1.1), [3.0, -2.0, 7.5]
    tilted = pinn_mesh(
        moved(boundary, matrix, shift),
        aux=moved(aux, matrix, shift),
        size=(21, 11),
        method="elliptic",
    )
    # same cells, same quality; points in the user's plane, boundary nodes on the input
    np.testing.assert_allclose(
        tilted.cell_data["MaxIncludedAngle"], flat.cell_data["MaxIncludedAngle"], atol=1e-6
    )
    normal = matrix @ [0.0, 0.0, 1.0]
    assert np.abs((tilted.points - shift) @ normal).max() < 1e-9
    np.testing.assert_allclose(tilted.points, flat.points @ matrix.T + shift, atol=1e-9)


def test_xz_plane_from_the_command_line(tmp_path, fig2):
    boundary, aux = fig2
    swap = np.array([[1.0, 0, 0], [0, 0, 1], [0, 1, 0]])  # (x, y, 0) -> (x, 0, y): y = 0
    moved(boundary, swap, [0, 2.0, 0]).save(tmp_path / "b.vtp")
    moved(aux, swap, [0, 2.0, 0]).save(tmp_path / "a.vtp")
    out = tmp_path / "g.vts"
    assert (
        main(
            [
                str(tmp_path / "b.vtp"),
                "--aux",
                str(tmp_path / "a.vtp"),
                "--size",
                "21",
                "11",
                "--method",
                "tfi",
                "-o",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    grid = pv.read(out)
    assert np.allclose(grid.points[:, 1], 2.0)
    # xi along x and eta up (+z): node (0, 0) is corner 0 of the XZ drawing, as in the xy one
    flat = pinn_mesh(boundary, size=(21, 11), method="tfi")
    np.testing.assert_allclose(grid.points[:, [0, 2]], flat.points[:, :2], atol=1e-9)


def test_constant_z_is_kept():
    boundary = load_boundary(EXAMPLES / "wavy.vtp")
    ring = boundary.frame.to_user(boundary.ring)
    lifted = Boundary.from_points(np.column_stack([ring, np.full(len(ring), 5.0)]))
    assert lifted.plane.is_horizontal
    flat = Boundary.from_points(ring)
    np.testing.assert_array_equal(lifted.ring, flat.ring)  # meshed exactly as before
    result = Mesher(make_settings("tfi")).fit(lifted).predict(11, 6)
    assert np.all(result.points3d[..., 2] == 5.0)


def test_non_planar_boundary_says_how_far(tmp_path, capsys):
    t = np.linspace(0, 1, 10, endpoint=False)
    square = np.concatenate(
        [
            np.column_stack([t, 0 * t]),
            np.column_stack([1 + 0 * t, t]),
            np.column_stack([1 - t, 1 + 0 * t]),
            np.column_stack([0 * t, 1 - t]),
        ]
    )
    z = np.where(np.arange(len(square)) == 15, 0.05, 0.0)  # one point 0.05 off: a dent
    path = tmp_path / "warped.csv"
    np.savetxt(path, np.column_stack([square, z]), delimiter=",")
    assert main([str(path), "-o", str(tmp_path / "g.vts"), "--method", "tfi"]) == 2
    err = capsys.readouterr().err
    assert "is not planar" in err and "up to 0.04" in err and "% of its size" in err


def test_aux_line_off_the_plane_is_named(tmp_path, fig2):
    boundary, aux = fig2
    shifted = aux.copy()
    shifted.points = aux.points + [0.0, 0.0, 0.3]
    shifted.save(tmp_path / "a.vtp")
    b = load_boundary(EXAMPLES / "fig2.vtp")
    with pytest.raises(InputError, match="line 0.*off the boundary's plane"):
        load_aux([tmp_path / "a.vtp"], b)


def test_saved_model_keeps_its_plane(tmp_path, fig2):
    boundary, _ = fig2
    matrix, shift = rotation(1.0, 0.5), [0.0, 1.0, -4.0]
    path = tmp_path / "b.vtp"
    moved(boundary, matrix, shift).save(path)
    tilted = load_boundary(path)
    mesher = Mesher(make_settings("pinn", **SHORT, lattice=(11, 6))).fit(tilted)
    mesher.save(tmp_path / "m.pt")
    again = Mesher.load(tmp_path / "m.pt", load_boundary(path)).predict(11, 6)
    np.testing.assert_allclose(again.points3d, mesher.predict(11, 6).points3d, atol=1e-9)
    assert isinstance(again.plane, Plane) and not again.plane.is_horizontal


def test_a_cached_mesher_is_not_reused_for_another_plane(fig2):
    from pinn_engine.kinds.four_sided.cache import MeshCache

    boundary, _ = fig2
    cache = MeshCache()
    pinn_mesh(boundary, size=(11, 6), method="tfi", cache=cache)
    lifted = pinn_mesh(
        moved(boundary, np.eye(3), [0.0, 0.0, 5.0]), size=(11, 6), method="tfi", cache=cache
    )
    assert np.all(lifted.points[:, 2] == 5.0)


def test_tilted_grid_exports_extrude_along_its_normal(tmp_path, fig2):
    import gmsh

    from pinn_engine.io.export import write

    boundary, _ = fig2
    matrix = rotation(0.4, 1.1)
    tilted = pinn_mesh(moved(boundary, matrix, [1.0, 2.0, 3.0]), size=(11, 6), method="tfi")
    out = write(tilted, tmp_path / "g.msh", extrude=0.5)
    gmsh.initialize()
    try:
        gmsh.open(str(out))
        _, coords, _ = gmsh.model.mesh.getNodes()
    finally:
        gmsh.finalize()
    normal = matrix @ [0.0, 0.0, 1.0]
    offsets = np.round((coords.reshape(-1, 3) - [1.0, 2.0, 3.0]) @ normal, 9)
    assert set(np.abs(offsets)) == {0.0, 0.5}  # the two layers, 0.5 apart along the normal
    with pytest.raises(InputError, match="SU2's 2D format needs a grid in a plane z = const"):
        write(tilted, tmp_path / "g.su2")
    assert not (tmp_path / "g.su2").exists()
