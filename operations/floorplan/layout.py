"""How a floor was drawn, so that a typing that fails can ask for another draw.

``make_floor`` attaches a :class:`LayoutRecipe` to its plan. When ``type_rooms`` finds no
typing (or no doors the access rules allow) for the layout, it asks the recipe for a
re-draw: the same footprint, corridors and rules, cut from the next random stream of
the same shape (``("redraw", attempt)`` under the shape's key), with cut positions
aimed at the areas the table asks for (:func:`.treemap.partition_to_areas`). Re-draws
are bounded and deterministic for the seed (docs/architecture.md, "Floor plans").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from cga.model import FloorPlan, FloorSettings, StairCore
from cga.randomness import stream

from .assemble import plan_from_dcel
from .bsp import FixedFace
from .treemap import partition_to_areas

__all__ = ["LayoutRecipe"]

Point = tuple[float, float]


@dataclass(frozen=True)
class LayoutRecipe:
    """Everything ``make_floor`` used to draw a floor, except the random stream.

    ``rooms`` is the number of rooms wanted besides the fixed faces; ``key`` names the
    shape's random stream (seed and path) so re-draws are reproducible.
    """

    footprint: tuple[Point, ...]
    rooms: int
    fixed: tuple[FixedFace, ...]
    min_width: float
    min_area: float
    min_contact: float
    settings: FloorSettings
    index: int
    elevation: float
    height: float
    seed: int
    key: tuple[str, ...]
    core: StairCore | None = None
    """The building's stair core, the first of ``fixed``, kept on every re-draw."""

    @property
    def free_rooms(self) -> int:
        """Rooms the BSP makes (besides fixed rooms that are not circulation)."""
        return self.rooms - sum(not f.circulation for f in self.fixed)

    def redraw(self, attempt: int, areas: Sequence[float]) -> FloorPlan:
        """The floor drawn again from stream ``attempt``, aimed at ``areas``.

        Raises
        ------
        ValueError
            The partition refuses the footprint (never for a footprint that was drawn
            once already).
        """
        rng = stream(self.seed, (*self.key, "redraw", str(attempt)))
        result = partition_to_areas(self.footprint, areas, rng, min_width=self.min_width,
                                    min_area=self.min_area, fixed=self.fixed,
                                    min_contact=self.min_contact)
        plan = plan_from_dcel(result.dcel, settings=self.settings, index=self.index,
                              elevation=self.elevation, height=self.height,
                              circulation=result.circulation)
        if self.core is not None:
            plan = plan.with_stair_core(self.core)
        return plan.with_changes(layout=self)
