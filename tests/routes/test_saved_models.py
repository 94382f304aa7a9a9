"""A four-sided model saved by the command line and loaded by it at another size, and refused
for another boundary."""

from __future__ import annotations

from helpers import EXAMPLES

from pinn_engine.routes.cli import main


def test_cli_pinn_with_save_and_load(tmp_path, capsys):
    model = tmp_path / "m.pt"
    args = [
        str(EXAMPLES / "wavy.vtp"),
        "--aux",
        str(EXAMPLES / "wavy_aux.vtp"),
        "--epochs",
        "60",
        "--lbfgs",
        "5",
        "--quiet",
    ]
    assert main(args + ["-o", str(tmp_path / "a.vts"), "--save-model", str(model)]) == 0
    assert (
        main(
            [
                str(EXAMPLES / "wavy.vtp"),
                "--load-model",
                str(model),
                "--size",
                "101",
                "51",
                "-o",
                str(tmp_path / "b.vts"),
                "--quiet",
            ]
        )
        == 0
    )
    assert (tmp_path / "b.vts").stat().st_size > 0
    # a model for another boundary is refused with a clear error
    assert (
        main(
            [str(EXAMPLES / "fig2.vtp"), "--load-model", str(model), "-o", str(tmp_path / "c.vts")]
        )
        == 2
    )
    assert "different boundary" in capsys.readouterr().err
