"""``component_split("side_faces"|"top"|"bottom"){...}``: a mass's faces as shapes
(docs/language.md).

* ``"side_faces"``: one vertical face per footprint edge, in the footprint's
  counter-clockwise order (exterior ring first, then holes). With ``k`` successors, face
  ``i`` goes to successor ``min(i, k - 1)``: ``{A}`` gives every face to A, ``{A, B}``
  gives face 0 to A and the rest to B, ``{Facade, FrontFacade, Facade}`` singles out
  face 1. Each face gets ``attrs["index"] = i``.
* ``"top"`` / ``"bottom"``: the roof / ground polygon, one face, one successor.

Faces carry CGA scopes (x along the face, z the outward normal), so they can be split
further along their ``x`` and ``y``; horizontal faces can be extruded.
"""

from __future__ import annotations

import difflib
from typing import Any

from cga.errors import DerivationError
from cga.shape import Mass, Shape

from cga.operation import Child, Operation, OperationContext, Param
from .faces import bottom_face, side_faces, top_face

__all__ = ["ComponentSplit", "SELECTORS"]

SELECTORS = ("side_faces", "top", "bottom")


class ComponentSplit(Operation):
    """Faces of a mass: side faces (one per footprint edge), top or bottom."""

    name = "component_split"
    params = (Param("selector", "string", doc='"side_faces", "top" or "bottom"'),)
    min_successors = 1
    max_successors = None
    doc = 'component_split("side_faces"|"top"|"bottom"){...}: faces of a mass'

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        selector = args["selector"]
        if selector not in SELECTORS:
            close = difflib.get_close_matches(selector, SELECTORS, n=1)
            raise DerivationError(
                f"component_split selector must be one of {', '.join(map(repr, SELECTORS))}, "
                f"got {selector!r}", hint=f"did you mean {close[0]!r}?" if close else None)
        mass = shape.geometry
        if not isinstance(mass, Mass):
            raise DerivationError(f"component_split needs a mass; {shape.symbol} is a "
                                  f"{mass.kind} face")
        if selector == "side_faces":
            if not mass.height > 0:
                raise DerivationError(f"{shape.symbol} has no height, so it has no side faces",
                                      hint="extrude it first, e.g. extrude(10)")
            last = ctx.successor_count - 1
            return [Child(successor=min(i, last), geometry=face, scope=scope, attrs={"index": i})
                    for i, (face, scope) in enumerate(side_faces(mass))]
        if ctx.successor_count != 1:
            raise DerivationError(f'component_split("{selector}") makes one face; give one '
                                  f"successor, not {ctx.successor_count}")
        if mass.footprint.interiors:
            raise DerivationError(f'component_split("{selector}") cannot make a face of a '
                                  f"footprint with holes")
        face, scope = top_face(mass) if selector == "top" else bottom_face(mass)
        return [Child(successor=0, geometry=face, scope=scope, attrs={"index": 0})]
