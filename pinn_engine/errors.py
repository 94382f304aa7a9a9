"""Exceptions that carry a one-line, user-facing message."""

from __future__ import annotations


class PinnMeshError(Exception):
    """Any failure pinn-mesh reports to a user as one line (CLI exit status 2)."""


class InputError(PinnMeshError):
    """Bad boundary, auxiliary line or option; the message names the problem and the source."""

    def __init__(self, message: str, source: str | None = None) -> None:
        self.source = source
        super().__init__(f"{source}: {message}" if source else message)


class TrainingError(PinnMeshError):
    """Training diverged or was cancelled; no grid is produced."""


class TrainingCancelled(TrainingError):
    """The progress callback asked training to stop."""
