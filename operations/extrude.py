"""``extrude(height)``: give a footprint height (docs/language.md).

A mass's footprint is extruded from the mass's base to ``height`` (an existing height is
replaced, so ``extrude`` on the lot makes the building's body). A horizontal face (the
``top`` or ``bottom`` of a mass) is extruded along its outward normal into a new mass:
up from a roof, down from a floor. Side faces would need prisms that are not vertical;
they are refused with a message rather than approximated.
"""

from __future__ import annotations

from typing import Any

from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.errors import DerivationError
from cga.shape import Face, Mass, Shape

from cga.operation import Child, Operation, OperationContext, Param, is_number

__all__ = ["MIN_HEIGHT", "Extrude"]

_HORIZONTAL = 1e-9

MIN_HEIGHT = 1e-6
"""Least prism height (m): a micrometre, the grid plans and meshes are rounded to; below
it a prism has no volume to mesh (``units = 1e-9`` made nanometre buildings)."""


class Extrude(Operation):
    """Footprint → prism of the given height."""

    name = "extrude"
    params = (Param("height", "length", doc="height of the prism"),)
    doc = "extrude(height): footprint polygon → prism of height `height`"

    def check_values(self, args: dict[str, Any], units: float) -> None:
        height = args["height"]
        if is_number(height) and not height > 0:
            raise DerivationError(f"extrude height must be positive, got {height / units:g}")
        if is_number(height) and height < MIN_HEIGHT:
            raise DerivationError(f"extrude height {height / units:g} is {height:.3g} m, below "
                                  f"a micrometre", hint="check the grammar's units (metres per unit)")

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        self.check_values(args, ctx.units)
        height = args["height"]
        geometry = shape.geometry
        if isinstance(geometry, Mass):
            mass = Mass(footprint=geometry.footprint, base=geometry.base, height=height)
        else:
            mass = _extrude_face(geometry, height)
        return [Child(successor=0, geometry=mass, scope=mass.scope())]


def _extrude_face(face: Face, height: float) -> Mass:
    normal = face.normal()
    if abs(abs(normal[1]) - 1.0) > _HORIZONTAL:
        raise DerivationError(
            f"extrude works on masses and horizontal faces; this {face.kind} face is not "
            f"horizontal", hint="extrude the footprint before component_split, or use the "
                                "'top'/'bottom' faces")
    footprint = orient(Polygon([(x, z) for x, _, z in face.vertices]), sign=1.0)
    level = face.vertices[0][1]
    base = level if normal[1] > 0 else level - height
    return Mass(footprint=footprint, base=base, height=height)
