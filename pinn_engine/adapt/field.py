"""The field a grid is adapted to (SPEC 14): one array of any VTK dataset (a solver's
result: an OpenFOAM case through VTK's reader, ``.vtu``, ``.vts``, ``.vtm``, ...), a point
or cell array, a vector by its magnitude, sampled at any points inside the domain."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import (
    vtkCompositeDataSet,
    vtkDataObject,
    vtkDataSet,
    vtkPolyData,
)

from pinn_engine.errors import InputError

# A node lies in the field's domain when it is this share of the field's diagonal or less
# from its cells: a curved wall's grid nodes lie on the curve, a solver's cells on its chords
COVER_TOL = 0.01
FOAM_SUFFIXES = (".foam", ".openfoam")
# The image the field is sampled on while a grid is adapted: its step is the spacing of the
# field's own points at this percentile (a solver's finest cells, at a wall, keep their
# detail), between these many points a side
SPACING_PERCENTILE = 5
MIN_IMAGE_SIDE, IMAGE_SIDE = 256, 2048
# the field's points whose nearest-point gaps give the spacing, at most (evenly strided: a
# percentile of this many is the whole set's to a few per cent, at a tenth of the time for
# a solver's million points)
SPACING_SAMPLE = 20_000
# nearest points looked at for a gap: coinciding points (a 2D case's two planes, blocks
# that share a face) are skipped, up to this many at one place
COINCIDING = 8


def _reader(path: Path):
    """VTK's reader of ``path`` (an OpenFOAM case at its last time, the XML formats, the
    legacy format)."""
    suffix = path.suffix.lower()
    if suffix in FOAM_SUFFIXES:
        from vtkmodules.vtkIOGeometry import vtkOpenFOAMReader

        reader = vtkOpenFOAMReader()
        reader.SetFileName(str(path))
        reader.UpdateInformation()
        times = reader.GetTimeValues()
        if times is not None and times.GetNumberOfTuples():
            reader.UpdateTimeStep(times.GetValue(times.GetNumberOfTuples() - 1))
        return reader
    if suffix == ".vtk":
        from vtkmodules.vtkIOLegacy import vtkDataSetReader

        reader = vtkDataSetReader()
    else:
        from vtkmodules.vtkIOXML import vtkXMLGenericDataObjectReader

        reader = vtkXMLGenericDataObjectReader()
    reader.SetFileName(str(path))
    return reader


def read_field(spec: str) -> Field:
    """The field of ``FILE:ARRAY`` (the last colon splits them)."""
    path, sep, array = str(spec).rpartition(":")
    if not sep or not path or not array:
        raise InputError(f"--adapt {spec}: write FILE:ARRAY, e.g. result.foam:U")
    return read_field_file(path, array)


def read_field_file(path: str | os.PathLike, array: str) -> Field:
    """The field ``array`` of the dataset in ``path``."""
    from vtkmodules.vtkCommonCore import vtkObject

    path = Path(path)
    if not path.is_file():
        raise InputError("file not found", str(path))
    reader = _reader(path)
    previous = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        reader.Update()
    finally:
        vtkObject.SetGlobalWarningDisplay(previous)
    data = reader.GetOutputDataObject(0)
    if data is None:
        raise InputError("VTK reads no dataset from it", str(path))
    return Field(data, array, str(path))


def _leaves(data: vtkDataObject) -> list[vtkDataSet]:
    """The datasets of ``data`` (itself, or a composite dataset's leaves)."""
    if isinstance(data, vtkCompositeDataSet):
        out = []
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaf = it.GetCurrentDataObject()
            if isinstance(leaf, vtkDataSet) and leaf.GetNumberOfPoints():
                out.append(leaf)
            it.GoToNextItem()
        return out
    return [data] if isinstance(data, vtkDataSet) and data.GetNumberOfPoints() else []


def _names(leaves: list[vtkDataSet]) -> str:
    """The arrays there are, for the message naming them."""
    found = []
    for leaf in leaves:
        for kind, fd in (("point", leaf.GetPointData()), ("cell", leaf.GetCellData())):
            for k in range(fd.GetNumberOfArrays()):
                name = fd.GetArrayName(k)
                if name and f"{name} ({kind})" not in found:
                    found.append(f"{name} ({kind})")
    return ", ".join(found) or "none"


def _dimension(leaf: vtkDataSet) -> int:
    """The dimension of a dataset's cells (a solver's volume 3, its patches 2)."""
    return leaf.GetCell(0).GetCellDimension() if leaf.GetNumberOfCells() else 0


def _first_array(leaves: list[vtkDataSet], source: str) -> str:
    """The first point array of the datasets, else their first cell array."""
    for kind in ("point", "cell"):
        for leaf in leaves:
            fd = leaf.GetPointData() if kind == "point" else leaf.GetCellData()
            for k in range(fd.GetNumberOfArrays()):
                if fd.GetArrayName(k):
                    return fd.GetArrayName(k)
    raise InputError("holds no point or cell array to adapt to", source)


class Field:
    """``array`` of the VTK data ``data`` (None: its first point array, else its first
    cell array) as point values (cell values averaged to the points, vectors by their
    magnitude); ``source`` names it in messages."""

    def __init__(self, data: vtkDataObject, array: str | None, source: str = "field") -> None:
        from vtkmodules.vtkFiltersCore import vtkAppendFilter, vtkCellDataToPointData

        leaves = _leaves(data)
        array = array or _first_array(leaves, source)
        self.array, self.source = array, source
        having = [
            leaf
            for leaf in leaves
            if leaf.GetPointData().GetArray(array) is not None
            or leaf.GetCellData().GetArray(array) is not None
        ]
        if not having:
            raise InputError(
                f"has no array {array!r}; the arrays there are: {_names(leaves)}", source
            )
        top = max(_dimension(leaf) for leaf in having)  # a solver's volume, not its patches
        append = vtkAppendFilter()
        for leaf in having:
            if _dimension(leaf) == top:
                if leaf.GetPointData().GetArray(array) is None:
                    to_points = vtkCellDataToPointData()
                    to_points.SetInputData(leaf)
                    to_points.Update()
                    leaf = to_points.GetOutput()
                append.AddInputData(self._scalar(leaf))
        append.Update()
        self.data = append.GetOutput()
        self.bounds = np.array(self.data.GetBounds()).reshape(3, 2)
        self.diagonal = float(np.linalg.norm(self.bounds[:, 1] - self.bounds[:, 0]))
        self._probe = None
        self._image = None

    def _scalar(self, leaf: vtkDataSet) -> vtkDataSet:
        """A copy of ``leaf`` whose point data is the field as one scalar ``f``."""
        values = vtk_to_numpy(leaf.GetPointData().GetArray(self.array)).astype(float)
        if values.ndim > 1:
            values = np.linalg.norm(values, axis=1)
        out = leaf.NewInstance()
        out.ShallowCopy(leaf)
        out.GetPointData().Initialize()
        out.GetCellData().Initialize()
        arr = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        arr.SetName("f")
        out.GetPointData().SetScalars(arr)
        return out

    def _z(self) -> float:
        """The z at which 2D points are sampled: 0, or the middle of a solver's slab (a 2D
        OpenFOAM case is one cell thick) that does not hold z = 0."""
        lo, hi = self.bounds[2]
        return 0.0 if lo <= 0.0 <= hi else 0.5 * (lo + hi)

    def sample(self, xy: np.ndarray) -> np.ndarray:
        """The field at points ``xy`` (n, 2), bilinear on a fine image of it (made once by
        one probe: an adaptive solve samples thousands of times, and a probe of the dataset
        itself costs 4 to 40 ms each, by VTK's version)."""
        if self._image is None:
            self._image = self._imaged()
        return self._image(xy[:, ::-1])

    def _imaged(self):
        """The field probed on an image over its box: a step of its points' spacing (at
        ``SPACING_PERCENTILE``), ``IMAGE_SIDE`` points a side at most and ``MIN_IMAGE_SIDE``
        at least, points outside
        its cells given their nearest inside point's value (so that cells next to a wall
        interpolate the field, not zero); its bilinear interpolant of (y, x)."""
        from scipy.interpolate import RegularGridInterpolator
        from scipy.spatial import cKDTree

        (x0, x1), (y0, y1) = self.bounds[0], self.bounds[1]
        plane = self._all_points()[:, :2]
        some = plane[:: max(1, len(plane) // SPACING_SAMPLE)]
        near = cKDTree(plane).query(some, k=min(COINCIDING + 1, len(plane)))[0]
        near = np.where(near > 1e-9 * self.diagonal, near, np.inf).min(axis=1)
        gaps = near[np.isfinite(near)]
        h = max(float(np.percentile(gaps, SPACING_PERCENTILE)), 1e-12 * self.diagonal)
        nx = int(np.clip(np.ceil((x1 - x0) / h), MIN_IMAGE_SIDE, IMAGE_SIDE)) + 1
        ny = int(np.clip(np.ceil((y1 - y0) / h), MIN_IMAGE_SIDE, IMAGE_SIDE)) + 1
        x, y = np.linspace(x0, x1, nx), np.linspace(y0, y1, ny)
        xx, yy = np.meshgrid(x, y)
        values, valid = self.probe(np.column_stack([xx.ravel(), yy.ravel()]))
        values, valid = values.reshape(ny, nx), valid.reshape(ny, nx)
        if valid.any() and not valid.all():
            from scipy.ndimage import distance_transform_edt  # a third of a second to import

            _, (jj, ii) = distance_transform_edt(~valid, return_indices=True)
            values = values[jj, ii]
        return RegularGridInterpolator((y, x), values, bounds_error=False, fill_value=None)

    def _all_points(self) -> np.ndarray:
        """The field's points (n, 3)."""
        return vtk_to_numpy(self.data.GetPoints().GetData()).astype(float)

    def probe(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The field at points ``xy`` (n, 2) probed in its cells, and whether each lies in
        them (a point outside takes the value of the field's nearest point)."""
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkFiltersCore import vtkProbeFilter

        if self._probe is None:
            from vtkmodules.vtkCommonDataModel import vtkStaticCellLocator

            locator = vtkStaticCellLocator()
            locator.SetDataSet(self.data)
            locator.BuildLocator()
            self._probe = vtkProbeFilter()
            self._probe.SetSourceData(self.data)
            if hasattr(self._probe, "SetCellLocator"):  # VTK 9.3 and later
                self._probe.SetCellLocator(locator)
            else:  # ParaView 5.11's VTK
                from vtkmodules.vtkCommonDataModel import vtkCellLocatorStrategy

                strategy = vtkCellLocatorStrategy()
                strategy.SetCellLocator(locator)
                self._probe.SetFindCellStrategy(strategy)
            self._probe.ComputeToleranceOff()
            self._probe.SetTolerance(1e-9 * self.diagonal)
            self._locator = locator
            self._points = vtk_to_numpy(self.data.GetPoints().GetData()).astype(float)
            self._values = vtk_to_numpy(self.data.GetPointData().GetArray("f")).astype(float)
        xyz = np.column_stack([xy, np.full(len(xy), self._z())])
        pts = vtkPoints()
        pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz), deep=True))
        poly = vtkPolyData()
        poly.SetPoints(pts)
        self._probe.SetInputData(poly)
        self._probe.Update()
        out = self._probe.GetOutput()
        values = vtk_to_numpy(out.GetPointData().GetArray("f")).astype(float).copy()
        valid = vtk_to_numpy(out.GetPointData().GetArray("vtkValidPointMask")).astype(bool)
        if not valid.all():
            from scipy.spatial import cKDTree

            if not hasattr(self, "_tree"):
                self._tree = cKDTree(self._points)
            _, nearest = self._tree.query(xyz[~valid])
            values[~valid] = self._values[nearest]
        return values, valid

    def outside(self, xy: np.ndarray) -> np.ndarray:
        """Which points ``xy`` (n, 2) lie farther than ``COVER_TOL`` of the field's
        diagonal from its cells."""
        _, valid = self.probe(xy)
        far = np.zeros(len(xy), dtype=bool)
        if valid.all():
            return far
        import vtkmodules.vtkCommonCore as core

        cell, sub, dist2 = core.reference(0), core.reference(0), core.reference(0.0)
        closest = [0.0, 0.0, 0.0]
        z = self._z()
        for k in np.flatnonzero(~valid):
            self._locator.FindClosestPoint([xy[k, 0], xy[k, 1], z], closest, cell, sub, dist2)
            far[k] = np.sqrt(dist2.get()) > COVER_TOL * self.diagonal
        return far

    def check_covers(self, xy: np.ndarray) -> None:
        """Refuse, in one line, a field that does not cover the nodes ``xy``."""
        far = self.outside(xy)
        if far.any():
            (x0, x1), (y0, y1) = self.bounds[0], self.bounds[1]
            p = xy[np.flatnonzero(far)[0]]
            raise InputError(
                f"the field {self.array!r} does not cover the domain: {int(far.sum())} of "
                f"{len(xy)} grid nodes lie outside its cells (the first at ({p[0]:.4g}, "
                f"{p[1]:.4g}); the field spans x {x0:.4g} to {x1:.4g}, y {y0:.4g} to "
                f"{y1:.4g}); give a result computed on this domain",
                self.source,
            )
