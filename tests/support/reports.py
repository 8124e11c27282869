"""A fixed check report for scenes built by hand in tests."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class FixedReport:
    """A :class:`cga.report.CheckReport` whose answers are given."""

    passed: bool = True
    details: dict[str, Any] = field(default_factory=dict)
    line: str = ""

    def summary(self) -> str:
        return self.line

    def to_dict(self) -> dict[str, Any]:
        return {"passed": self.passed, **self.details}
