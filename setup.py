"""The install's one step beyond pyproject.toml: compile the network's C++ jet kernels and
the body grids' march.

``build_jet`` runs with every build (``pip install``, ``pip install -e``, ``pip wheel``) and
puts each library beside its source (``native.build_packaged`` beside ``kernels.cpp``,
``marching.build_packaged`` beside ``march.cpp``), so that the first run does not compile
the kernels. It never fails the install: without a compiler the engine builds the kernels at
first use, and the march runs as NumPy operations. The wheel is then specific to this
platform.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from setuptools import Command, setup
from setuptools.command.build import build
from setuptools.dist import Distribution

JET = Path("pinn_engine", "neural", "jet")
BODIES = Path("pinn_engine", "bodies")


def _load(path: Path, name: str):
    """The module at ``path`` loaded by its path: the build environment has setuptools
    alone, and the packages' ``__init__`` import torch or NumPy (``native.py`` itself imports
    the package's ``errors``, ``marching.py`` nothing of it, both standard library only: the
    source folder goes on the path)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class BuildJet(Command):
    """Compile ``kernels.cpp`` and ``march.cpp`` into the built package (into the checkout
    when editable)."""

    description = "compile the network's C++ jet kernels and the body grids' march"
    user_options: list = []

    def initialize_options(self) -> None:
        self.build_lib = None
        self.editable_mode = False
        self.outputs: list[str] = []

    def finalize_options(self) -> None:
        self.set_undefined_options("build_py", ("build_lib", "build_lib"))

    def run(self) -> None:
        root = Path() if self.editable_mode else Path(self.build_lib)
        native = _load(JET / "native.py", "_pinn_native")
        marching = _load(BODIES / "marching.py", "_pinn_marching")
        for folder in (root / JET, root / BODIES):
            folder.mkdir(parents=True, exist_ok=True)
        built = [
            native.build_packaged(root / JET),
            marching.build_packaged(root / BODIES, native._compiler(), native._compile),
        ]
        self.outputs = [str(path) for path in built if path]

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
