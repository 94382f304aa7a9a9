"""The one version number, ``[project] version`` of pyproject.toml.

Read from the installed package's metadata; a checkout that is not installed (the ParaView
plugin imports ``pinn_engine`` from the checkout it lives in) reads its pyproject.toml.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version
from pathlib import Path


def _version() -> str:
    try:
        return version("pinn-mesh")
    except PackageNotFoundError:
        pass
    try:
        import tomllib  # Python 3.11+ (ParaView 5.11's Python is 3.11)

        pyproject = Path(__file__).resolve().parents[1] / "pyproject.toml"
        return tomllib.loads(pyproject.read_text())["project"]["version"]
    except (ImportError, OSError, KeyError):
        return "unknown"


__version__ = _version()
