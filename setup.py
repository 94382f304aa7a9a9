"""The install's one step beyond pyproject.toml: compile the network's C++ jet kernels.

``build_jet`` runs with every build (``pip install``, ``pip install -e``, ``pip wheel``) and
puts the library beside ``kernels.cpp`` (``native.build_packaged``), so that the first run
does not compile it. It never fails the install: without a compiler the engine builds the
library at first use, as before. The wheel is then specific to this platform.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from setuptools import Command, setup
from setuptools.command.build import build
from setuptools.dist import Distribution

JET = Path("pinn_engine", "neural", "jet")


def _native():
    """``native.py`` loaded by its path: the build environment has setuptools alone, and the
    jet package's ``__init__`` imports torch (``native.py`` itself imports the package's
    ``errors``, standard library only: the source folder goes on the path)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    spec = importlib.util.spec_from_file_location("_pinn_native", JET / "native.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class BuildJet(Command):
    """Compile ``kernels.cpp`` into the built package (into the checkout when editable)."""

    description = "compile the network's C++ jet kernels"
    user_options: list = []

    def initialize_options(self) -> None:
        self.build_lib = None
        self.editable_mode = False
        self.outputs: list[str] = []

    def finalize_options(self) -> None:
        self.set_undefined_options("build_py", ("build_lib", "build_lib"))

    def run(self) -> None:
        folder = JET if self.editable_mode else Path(self.build_lib) / JET
        folder.mkdir(parents=True, exist_ok=True)
        built = _native().build_packaged(folder)
        self.outputs = [str(built)] if built else []

    def get_outputs(self) -> list[str]:
        return self.outputs

    def get_output_mapping(self) -> dict[str, str]:
        return {}


class Build(build):
    sub_commands = [*build.sub_commands, ("build_jet", None)]


class BinaryDistribution(Distribution):
    """A distribution with a compiled library: its wheel is tagged for this platform."""

    def has_ext_modules(self) -> bool:
        return True


setup(cmdclass={"build": Build, "build_jet": BuildJet}, distclass=BinaryDistribution)
