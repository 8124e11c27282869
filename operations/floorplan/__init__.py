"""Floor partitioning for ``make_floor`` (docs/architecture.md, "Floor plans").

:mod:`.dcel` is the half-edge structure, :mod:`.bsp` cuts a footprint into rooms,
:mod:`.assemble` turns the result into a :class:`cga.model.FloorPlan`, :mod:`.openings`
places windows and :mod:`.rectangles` builds plans from hand-written rectangles (for rule
tests). The 3D walls and slabs are made from the final plan by :mod:`cga.meshing.solids`.
"""

from .dcel import DCEL, Face, HalfEdge, Vertex
from .rectangles import plan_from_rectangles

__all__ = ["DCEL", "Face", "HalfEdge", "Vertex", "plan_from_rectangles"]
