"""``repeated_split(axis, size){First, Rest}``: equal slices of about ``size`` (docs/language.md).

The extent along the axis is cut into ``n = max(1, round(extent / size))`` slices of
equal size (the remainder spread evenly; halves round up). The first slice goes to the
first successor and every other slice to the last successor, so with one successor all
slices share it. Each slice gets ``attrs["index"]`` = its number from 0; along ``y`` it
also gets ``attrs["floor"]`` = the same number and ``attrs["floors"]`` = the number of
slices, which is how a mass becomes storeys (and how ``make_floor`` knows the storey is
one of a stack that needs a stair).
"""

from __future__ import annotations

import math
from typing import Any

from cga.errors import DerivationError
from cga.shape import Shape

from cga.operation import Child, Operation, OperationContext, Param, is_number
from .slicing import check_piece_count, cut, extent

__all__ = ["RepeatedSplit", "slice_count"]


def slice_count(total: float, size: float) -> int:
    """``max(1, round(total / size))`` with halves rounded up."""
    return max(1, int(math.floor(total / size + 0.5)))


class RepeatedSplit(Operation):
    """Equal slices along an axis: first → first successor, others → last successor."""

    name = "repeated_split"
    params = (Param("axis", "axis", doc="x, y or z of the shape's scope"),
              Param("size", "length", doc="target slice size"))
    min_successors = 1
    max_successors = 2
    doc = "repeated_split(axis, size){First, Rest}: slices of about `size`"

    def check_values(self, args: dict[str, Any], units: float) -> None:
        size = args["size"]
        if is_number(size) and not size > 0:
            raise DerivationError(f"repeated_split size must be positive, got {size / units:g}")

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        self.check_values(args, ctx.units)
        axis, size = args["axis"], args["size"]
        total = extent(shape, axis)
        n = slice_count(total, size)
        check_piece_count(n, f"repeated_split size {size / ctx.units:g} on an extent of "
                             f"{total / ctx.units:g}", ctx.shapes_left)
        bounds = [total * i / n for i in range(n)] + [total]
        pieces = cut(shape, axis, list(zip(bounds[:-1], bounds[1:])))
        last = ctx.successor_count - 1
        children = []
        for k, geometry, scope in pieces:
            attrs = {"index": k, "floor": k, "floors": n} if axis == "y" else {"index": k}
            children.append(Child(successor=0 if k == 0 else last, geometry=geometry,
                                  scope=scope, attrs=attrs))
        return children
