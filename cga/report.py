"""What every check of a built scene reports (docs/architecture.md, "Checks").

The physics and navigability checks return their own report classes; both satisfy
:class:`CheckReport`, which is all the pipeline, the summary, the batch manifest and the
scene JSON need. Reports stay objects in ``Scene.checks``; only the JSON exporter turns
them into dicts (:meth:`CheckReport.to_dict` plus the one-line summary).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

__all__ = ["CheckReport"]


@runtime_checkable
class CheckReport(Protocol):
    """The result of one check of a scene."""

    @property
    def passed(self) -> bool:
        """Whether the scene passes this check."""
        ...

    def summary(self) -> str:
        """One line for the terminal, e.g. ``physics: 41/41 items at rest``."""
        ...

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready data (``passed`` plus details), deterministic for a
        seed (no wall-clock times)."""
        ...
