"""The test session's set-up (shared values and helpers are in helpers.py)."""

from __future__ import annotations

import os

# off-screen pictures without an X display
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
