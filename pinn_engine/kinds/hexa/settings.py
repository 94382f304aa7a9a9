"""A six-faced 3D domain's settings (SPEC 11): the shared core, three node counts, spacing
and orthogonality on its patches imin ... kmax (or faceN), and the angle that ends a face of
a surface without FaceId."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from pinn_engine.errors import InputError
from pinn_engine.settings import (
    FACE_ANGLE,
    HEXA_LBFGS_ITERATIONS,
    HEXA_METHODS,
    HEXA_SIZE,
    MIN_HEXA_NODES,
    OPPOSITE_NODES,
    Counts,
    Interval,
    Options,
    Places,
    Settings,
    parse_patch_spacing,
    parse_patch_walls,
    register,
)


@register("hexa")
@dataclass(frozen=True)
class HexaSettings(Settings):
    """The core's settings and a six-faced domain's: its faces end where neighbouring
    triangles' normals differ by more than ``face_angle`` degrees (a surface without
    FaceId), and ``spacing`` and ``orthogonal`` name its patches."""

    CONSTRAINTS: ClassVar[dict] = {
        **Settings.CONSTRAINTS,
        "method": Options(HEXA_METHODS),
        "size": Counts((3,), MIN_HEXA_NODES, "nodes along i, j and k"),
        "spacing": Places(True, (), "first-edge length per patch"),
        "orthogonal": Places(False, (), "patches that grid lines leave at 90 degrees"),
        "face_angle": Interval(
            float,
            0.0,
            180.0,
            "six-faced surface without FaceId (an STL): faces end where neighbouring "
            "triangles' normals differ by more than this many degrees",
        ),
    }
    # its L-BFGS run, under every preset (settings.HEXA_LBFGS_ITERATIONS)
    OVER_PRESET: ClassVar[dict] = {"lbfgs_iterations": HEXA_LBFGS_ITERATIONS}

    size: tuple[int, ...] = HEXA_SIZE
    face_angle: float = FACE_ANGLE

    @classmethod
    def refusal(cls, name: str, value, problem: str) -> Exception:
        if name == "method":  # in the route's words
            return InputError(
                f"{{method:{value}}}: six-faced 3D domains are meshed by {', '.join(HEXA_METHODS)}"
            )
        return super().refusal(name, value, problem)

    @classmethod
    def read_places(cls, spacing, orthogonal) -> dict:
        """``spacing`` and ``orthogonal`` read as patches, in the route's words."""
        return {
            "spacing": parse_patch_spacing(spacing),
            "orthogonal": parse_patch_walls(orthogonal),
        }

    def check(self) -> None:
        """The core's start rule; orthogonal patches need a method that turns grid lines,
        and two opposite ones a first layer each."""
        self.check_start()
        if self.orthogonal and self.method == "tfi":
            raise InputError(
                f"{{orthogonal}} {','.join(self.orthogonal)}: use {{method:elliptic}} or pinn "
                "(tfi's grid lines cannot turn to a patch's normal)"
            )
        for axis, name in enumerate("ijk"):
            if {f"{name}min", f"{name}max"} <= set(self.orthogonal) and self.size[
                axis
            ] < OPPOSITE_NODES:
                raise InputError(
                    f"{{orthogonal}} {name}min,{name}max: give at least {OPPOSITE_NODES} nodes "
                    f"along {name} ({{size}}), one first layer for each"
                )
