"""The Scene: one object with everything a consumer of a build needs.

The evaluator derives a shape tree; :func:`cga.pipeline.build` collects its terminal shapes
into a Scene: the floor plans (rooms, walls, doors, windows, furniture) and any other
terminal geometry (masses and faces of grammars that do not make floors). Exporters and
checks read a Scene and nothing upstream of it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .model import Diagnostic, FloorPlan
from .shape import Shape

__all__ = ["Scene", "SceneNode"]


@dataclass(frozen=True)
class SceneNode:
    """A named piece of output geometry, in world coordinates (metres, y up).

    ``path`` is the semantic node name, e.g. ``floor1/room3_Kitchen/wall2`` or
    ``floor0/room1_Livingroom/furniture/sofa``. ``kind`` is one of ``wall``, ``slab``,
    ``ceiling``, ``furniture``, ``mass``, ``face``. ``parts`` are the convex pieces of a
    furniture item (physics uses them as a compound body); ``static`` bodies do not move.
    """

    path: str
    kind: str
    mesh: Any  # trimesh.Trimesh
    extras: dict[str, Any] = field(default_factory=dict)
    static: bool = True
    parts: tuple[Any, ...] = ()


@dataclass
class Scene:
    """The result of a build.

    ``terminals`` are the leaves of the shape tree in derivation order; those with a
    ``plan`` are storeys, the rest plain geometry. ``checks`` is filled by the physics
    and navigability checks; ``timings`` maps stage name → seconds.
    """

    name: str
    seed: int
    units: float
    terminals: list[Shape]
    source: Path | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    checks: dict[str, Any] = field(default_factory=dict)

    @property
    def floors(self) -> list[FloorPlan]:
        """Floor plans ordered by floor index."""
        plans = [s.plan for s in self.terminals if s.plan is not None]
        return sorted(plans, key=lambda p: p.index)

    @property
    def masses(self) -> list[Shape]:
        """Terminal shapes that are plain geometry (not storeys)."""
        return [s for s in self.terminals if s.plan is None]

    def all_diagnostics(self) -> list[Diagnostic]:
        """Build diagnostics followed by those recorded on each floor plan."""
        out = list(self.diagnostics)
        for plan in self.floors:
            out.extend(plan.diagnostics)
        return out
