"""Floor partitioning for ``make_floor`` (DESIGN §6).

:mod:`.dcel` is the half-edge structure, :mod:`.bsp` cuts a footprint into rooms,
:mod:`.assemble` turns the result into a :class:`cga.model.FloorPlan`, :mod:`.openings`
places windows, :mod:`.rectangles` builds plans from hand-written rectangles (for rule
tests) and :mod:`.solids` makes the 3D walls and slabs at meshing time.
"""

from .dcel import DCEL, Face, HalfEdge, Vertex
from .rectangles import plan_from_rectangles

__all__ = ["DCEL", "Face", "HalfEdge", "Vertex", "plan_from_rectangles"]
