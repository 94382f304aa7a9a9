"""What a job gives, whatever the domain kind: the one result every route presents."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkDataObject


@dataclass
class Outcome:
    """A job's result: its VTK data (the ``vtkStructuredGrid`` of SPEC 3 and 11, or the
    ``vtkMultiBlockDataSet`` of SPEC 10), the run's report (what ``--report`` writes), each
    block's nodes in VTK's index order (i fastest: ``(nj, ni, 2)`` in-plane, ``(nk, nj, ni,
    3)`` in 3D), the loss history, whether this run trained a network (not re-used one),
    the model ``--save-model`` writes (a fitted ``Mesher`` or a ``HexaModel``; None when no
    network), for blocks the block edges meshed and for a dictionary its merged mesh."""

    kind: str
    data: vtkDataObject
    report: dict
    grids: list[np.ndarray]
    history: dict[str, list[float]] = field(default_factory=dict)
    trained: bool = False
    model: object | None = None
    edges: list[np.ndarray] = field(default_factory=list)
    mesh: object | None = None  # a dictionary's merged hexahedra (``blocks3d.mesh.DictResult``)

    @property
    def quality(self) -> dict:
        """The quality figures of SPEC 6 over every cell."""
        return self.report["quality"]


def network_trained(report: dict) -> bool:
    """Whether the run of ``report`` trained a network: it has a training whose network was
    not skipped (``kinds.untrained``: the start kept untrained, no training time spent)."""
    training = report.get("training")
    return bool(training) and not training.get("skipped")
