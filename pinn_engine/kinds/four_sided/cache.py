"""Fitted meshers kept for re-use by the VTK algorithm and the pyvista accessor."""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.settings import Settings

if TYPE_CHECKING:  # the engine's numerics are imported on first use (fast plugin loading)
    from pinn_engine.geometry.auxlines import AuxLine
    from pinn_engine.geometry.boundary import Boundary
    from pinn_engine.kinds.four_sided.mesher import Mesher


def _digest(*arrays) -> str:
    h = hashlib.sha1()
    for a in arrays:
        if a is None:
            h.update(b"<none>")
            continue
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()


def data_key(boundary: Boundary, aux_lines: Sequence[AuxLine]) -> tuple[str, str]:
    """Fingerprints of the inputs of a fitted mesher: the boundary (ring, corners, frame and
    plane) and the mapped auxiliary lines."""
    b = _digest(
        boundary.ring,
        np.asarray(boundary.corners),
        boundary.frame.origin,
        np.asarray([boundary.frame.scale]),
        boundary.plane.origin,
        boundary.plane.axes,
    )
    a = _digest(*[x for line in aux_lines for x in (line.xy, line.xi_eta)])
    return b, f"{len(aux_lines)}:{a}"


def _sizeless(key: tuple) -> tuple:
    """A cache key without its lattice: the same inputs and network at any size."""
    return (*key[:2], tuple(item for item in key[2] if item[0] != "lattice"))


class MeshCache:
    """Fitted meshers keyed by (boundary, auxiliary lines, ``Settings.training_key()``).

    ``fitted`` trains only when that key is new; a change of anything training does not depend
    on re-uses the trained network through ``Mesher.predict``. The grid size is part of the
    key under the elliptic warm start (``Settings.lattice``), not otherwise; there a network
    trained at another size is tried first (``trained_elsewhere``, resize.py). A training
    stopped early (time limit, stop request) is not kept.
    """

    def __init__(self, capacity: int = 4) -> None:
        self.capacity = capacity
        self.trainings = 0  # networks trained (pinn, mgnet) through this cache; no start kept
        self._entries: OrderedDict[tuple, Mesher] = OrderedDict()

    def key(self, boundary: Boundary, aux_lines: Sequence[AuxLine], settings: Settings) -> tuple:
        aux = aux_lines if settings.method == "pinn" else ()
        return (*data_key(boundary, aux), settings.training_key())

    def fitted(
        self,
        boundary: Boundary,
        aux_lines: Sequence[AuxLine],
        settings: Settings,
        progress: Callable[[dict], bool | None] | None = None,
    ) -> tuple[Mesher, bool]:
        """A mesher fitted to these inputs and whether a network was trained for it now (not
        where the network could not win and its start is the map: ``kinds.untrained``)."""
        key = self.key(boundary, aux_lines, settings)
        mesher = self._entries.get(key)
        if mesher is not None:
            self._entries.move_to_end(key)
            mesher.settings = settings  # same training key; refreshes preset/device in reports
            return mesher, False
        from pinn_engine.kinds.four_sided.mesher import Mesher

        mesher = Mesher(settings).fit(boundary, aux_lines, progress)
        trained = mesher.model_ is not None and not mesher.model_.info.get("skipped")
        self.trainings += int(trained)
        if mesher.model_ is None or "stopped" not in mesher.model_.info:
            self._entries[key] = mesher  # a stopped training is not the asked one: train again
        while len(self._entries) > self.capacity:
            self._entries.popitem(last=False)
        return mesher, trained

    def trained_elsewhere(
        self, boundary: Boundary, aux_lines: Sequence[AuxLine], settings: Settings
    ) -> Mesher | None:
        """The newest mesher of these inputs whose network was trained on another lattice,
        every other training setting the same: what a size change re-evaluates (resize.py).
        None where these settings are cached themselves, where the lattice is no part of the
        key, or where the asked size's own run trains no network (``cannot_win``)."""
        from pinn_engine.kinds.untrained import cannot_win

        key = self.key(boundary, aux_lines, settings)
        if key in self._entries or all(name != "lattice" for name, _ in key[2]):
            return None
        if cannot_win(settings, aux_lines):
            return None
        for other in reversed(self._entries):
            mesher = self._entries[other]
            trained = mesher.model_ is not None and not mesher.model_.info.get("skipped")
            if trained and _sizeless(other) == _sizeless(key):
                return mesher
        return None

    def clear(self) -> None:
        self._entries.clear()
