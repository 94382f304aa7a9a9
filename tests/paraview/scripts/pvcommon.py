"""What the pvpython check scripts share (they import it from their own folder)."""

import contextlib
import io
import sys

from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow


@contextlib.contextmanager
def captured_errors():
    """Text written to vtkOutputWindow (and Python's stderr) inside the block."""
    got = {"vtk": "", "stderr": ""}
    old_window, window = vtkOutputWindow.GetInstance(), vtkStringOutputWindow()
    old_err, buf = sys.stderr, io.StringIO()
    vtkOutputWindow.SetInstance(window)
    sys.stderr = buf
    try:
        yield got
    finally:
        sys.stderr = old_err
        vtkOutputWindow.SetInstance(old_window)
        got["vtk"], got["stderr"] = window.GetOutput(), buf.getvalue()
