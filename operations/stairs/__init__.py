"""Stairs and multi-storey buildings (DESIGN §12).

* :mod:`.design` sizes a stair (risers, rise, going) and places the building's stair
  core on the footprint: one rectangle, the same on every storey it serves;
* :mod:`.layout` lays out the stair between two consecutive storeys in that core
  (flights, half landing, floor landings, the stairwell cut into the slab above);
* :mod:`.access` restricts the core's doors to its landing.

The stair's solids and guard rails are made in the meshing layer
(:mod:`cga.meshing.stairs`).

The storeys of a building are derived one by one; :func:`cga.building.stack_storeys`
joins them afterwards (top storey, stairs between consecutive storeys).
"""

from .design import STAIR_KINDS, StairParams, core_for_storey, design_risers, place_core
from .layout import landing_rect, stair_between

__all__ = ["STAIR_KINDS", "StairParams", "core_for_storey", "design_risers", "place_core",
           "landing_rect", "stair_between"]
