"""``split(axis){ size : A | ~size : B | 'ratio : C }`` with CityEngine semantics
(docs/language.md).

Sizes along the axis, in order:

* absolute ``2 : A`` — exactly 2 (grammar units, converted to metres by the evaluator);
* relative ``'0.3 : B`` — 0.3 × the shape's extent along the axis;
* floating ``~1 : C`` — shares what is left after the absolute and relative parts, in
  proportion to the written sizes (``~1 | ~2`` take a third and two thirds).

Without floating parts, space left over at the end stays empty and parts that run past
the end are cut at it (a part starting past the end is dropped), as in CityEngine.

Repeat ``{ ... }*``: the pattern is laid out as often as fits. With floating parts the
count is the nearest whole number of patterns to ``extent / pattern size`` (at least one,
and no more than the absolute and relative parts leave room for) and the floating parts
stretch so the repetitions fill the extent exactly; without them, ``floor(extent /
pattern size)`` whole patterns are laid out (one cut short if not even one fits).

Every piece gets ``attrs["index"]``: its position among the laid-out parts.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from cga.errors import DerivationError
from cga.shape import Shape

from cga.operation import Child, Operation, OperationContext, Param
from .slicing import check_piece_count, cut, extent

__all__ = ["Split", "layout"]

_EPS = 1e-9


def _round_half_up(x: float) -> int:
    return int(math.floor(x + 0.5))


def _pattern(parts: Sequence[tuple[str, float, int]], total: float
             ) -> tuple[float, float]:
    """(fixed size, floating nominal size) of one pass over ``parts``."""
    fixed = sum(size * total if mode == "relative" else size
                for mode, size, _ in parts if mode != "floating")
    floating = sum(size for mode, size, _ in parts if mode == "floating")
    return fixed, floating


def layout(total: float, parts: Sequence[tuple[str, float, int]], repeat: bool,
           shapes_left: int | None = None) -> list[tuple[float, float, int]]:
    """Where each part goes along an axis of length ``total``.

    Parameters
    ----------
    total:
        The extent along the axis (metres), > 0.
    parts:
        ``(mode, size, successor)`` with mode ``"absolute"`` / ``"floating"`` (size in
        metres) or ``"relative"`` (size a ratio of ``total``).
    repeat:
        Lay the pattern out repeatedly (``{...}*``).
    shapes_left:
        How many more shapes the derivation may make (None: no budget); a repeat that
        needs more is refused before anything is cut.

    Returns
    -------
    list
        ``(start, end, successor)`` intervals, increasing, non-empty, within
        ``[0, total]``; consecutive intervals share their boundary value exactly, and
        when the parts fill the extent the last interval ends exactly at ``total``.
    """
    fixed, floating = _pattern(parts, total)
    count = 1
    if repeat:
        pattern = fixed + floating
        if pattern <= _EPS:
            raise DerivationError("a repeated split pattern needs a size greater than 0")
        if floating > 0:
            count = max(1, _round_half_up(total / pattern))
            while count > 1 and count * fixed > total + _EPS:
                count -= 1
        else:
            count = max(1, math.floor(total / pattern + _EPS))
        check_piece_count(count * len(parts), f"a repeated split pattern of {pattern:g} m "
                                              f"on an extent of {total:g} m", shapes_left)
    stretch = 0.0
    if floating > 0:
        stretch = max(0.0, total - count * fixed) / (count * floating)
    sizes: list[tuple[float, int]] = []
    for _ in range(count):
        for mode, size, successor in parts:
            if mode == "relative":
                length = size * total
            elif mode == "floating":
                length = size * stretch
            else:
                length = size
            sizes.append((length, successor))
    intervals: list[tuple[float, float, int]] = []
    position = 0.0
    for length, successor in sizes:
        start, end = position, min(position + length, total)
        position += length
        if abs(end - total) <= _EPS * max(1.0, total):
            end = total
        if end - start > _EPS:
            intervals.append((start, end, successor))
        if end >= total:
            break
    return intervals


class Split(Operation):
    """Cut a shape into sized parts along one axis."""

    name = "split"
    params = (Param("axis", "axis", doc="x, y or z of the shape's scope"),)
    min_successors = 1
    max_successors = None
    takes_split_parts = True
    doc = "split(axis){ size : A | ~size : B | 'ratio : C }*: sized parts along an axis"

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        axis = args["axis"]
        total = extent(shape, axis)
        intervals = layout(total, args["parts"], args["repeat"], ctx.shapes_left)
        pieces = cut(shape, axis, [(start, end) for start, end, _ in intervals])
        return [Child(successor=intervals[k][2], geometry=geometry, scope=scope,
                      attrs={"index": k})
                for k, geometry, scope in pieces]
