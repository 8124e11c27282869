"""Cut a shape into slabs along one scope axis: the geometry shared by the split operations.

``split`` and ``repeated_split`` decide *where* to cut (a list of intervals along the
axis); this module does the cutting:

* a mass along ``y`` is cut in height (each slab keeps the footprint);
* a mass along ``x`` or ``z`` has its footprint intersected with an axis-aligned box per
  interval (the mass scope is world-aligned); a piece of an L-shaped footprint may fall
  apart into several polygons, each returned as its own mass;
* a face along its scope's ``x`` or ``y`` is cut in the face's own 2D frame.

Neighbouring intervals share their boundary value exactly and the outermost boxes
reach past the shape's bounds, so the pieces tile the shape with no gap and no overlap
(checked by ``tests/property/test_derivation_props.py``).
"""

from __future__ import annotations

from collections.abc import Sequence

from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from cga.errors import BudgetError, DerivationError
from cga.shape import Face, Geometry, Mass, Scope, Shape

from .faces import face_from_polygon, face_polygon

__all__ = ["AXIS_INDEX", "MAX_PIECES", "extent", "check_piece_count", "polygons_of", "cut"]

AXIS_INDEX = {"x": 0, "y": 1, "z": 2}

_MIN_AREA = 1e-12

MAX_PIECES = 10_000
"""Most pieces one split may cut a shape into: a tiny size on a long extent would
otherwise make millions of shapes and never finish."""


def check_piece_count(count: int, what: str, shapes_left: int | None = None) -> None:
    """Refuse a cut into more than :data:`MAX_PIECES` pieces, or into more pieces than
    the derivation's shape budget has left (``shapes_left``, see
    :data:`cga.evaluator.MAX_SHAPES`), before any piece is cut.

    Raises
    ------
    DerivationError
        Naming ``what`` (the size asked for, e.g. ``"repeated_split size 0.001 m on
        16 m"``) and the limit.
    BudgetError
        The derivation would exceed its shape budget.
    """
    if count > MAX_PIECES:
        raise DerivationError(f"{what} would make {count:,} pieces; at most "
                              f"{MAX_PIECES:,} are allowed", hint="use a larger size")
    if shapes_left is not None and count > shapes_left:
        raise BudgetError(f"{what} would make {count:,} pieces, but the derivation may make "
                          f"only {shapes_left:,} more shapes (docs/limits.md)",
                          hint="use larger sizes, or split fewer shapes")


def extent(shape: Shape, axis: str) -> float:
    """The shape's size along ``axis`` (metres).

    Raises
    ------
    DerivationError
        The shape is flat along ``axis`` (a lot along y, a face along z), with what to do.
    """
    size = shape.scope.size[AXIS_INDEX[axis]]
    if size > 0:
        return float(size)
    if isinstance(shape.geometry, Face):
        raise DerivationError(f"a face is flat: it can be split along 'x' or 'y' of its "
                              f"scope, not '{axis}'")
    raise DerivationError(f"{shape.symbol} has no extent along '{axis}' (size 0)",
                          hint="extrude the footprint first, e.g. extrude(10)" if axis == "y"
                          else None)


def polygons_of(geometry: BaseGeometry) -> list[Polygon]:
    """The polygons (with area) of a shapely intersection result, in a stable order."""
    if isinstance(geometry, Polygon):
        parts = [geometry]
    else:
        parts = [g for g in getattr(geometry, "geoms", []) if isinstance(g, Polygon)]
    parts = [p for p in parts if p.area > _MIN_AREA]
    return sorted(parts, key=lambda p: (p.bounds[0], p.bounds[1], p.bounds[2], p.bounds[3]))


def _slab(bounds: tuple[float, float, float, float], axis: int, lo: float, hi: float,
          first: bool, last: bool) -> Polygon:
    """A box spanning ``[lo, hi]`` along ``axis`` (0 or 1) of 2D ``bounds``; the first and
    last slabs reach past the bounds so rounding never leaves a sliver uncovered."""
    mins, maxs = list(bounds[:2]), list(bounds[2:])
    margin = 1.0 + max(maxs[0] - mins[0], maxs[1] - mins[1])
    lows = [m - margin for m in mins]
    highs = [m + margin for m in maxs]
    lows[axis] = mins[axis] - margin if first else mins[axis] + lo
    highs[axis] = maxs[axis] + margin if last else mins[axis] + hi
    return box(lows[0], lows[1], highs[0], highs[1])


def _cut_mass(mass: Mass, axis: str, intervals: Sequence[tuple[float, float]]
              ) -> list[tuple[int, Geometry, Scope]]:
    pieces: list[tuple[int, Geometry, Scope]] = []
    last_index = len(intervals) - 1
    for k, (lo, hi) in enumerate(intervals):
        if axis == "y":
            piece = Mass(footprint=mass.footprint, base=mass.base + lo, height=hi - lo)
            pieces.append((k, piece, piece.scope()))
            continue
        slab = _slab(mass.footprint.bounds, 0 if axis == "x" else 1, lo, hi,
                     k == 0 and lo <= 0, k == last_index and hi >= _full(mass, axis))
        for polygon in polygons_of(mass.footprint.intersection(slab)):
            piece = Mass(footprint=polygon, base=mass.base, height=mass.height)
            pieces.append((k, piece, piece.scope()))
    return pieces


def _full(mass: Mass, axis: str) -> float:
    minx, minz, maxx, maxz = mass.footprint.bounds
    return (maxx - minx) if axis == "x" else (maxz - minz)


def _cut_face(face: Face, scope: Scope, axis: str, intervals: Sequence[tuple[float, float]]
              ) -> list[tuple[int, Geometry, Scope]]:
    local = face_polygon(face, scope)
    index = AXIS_INDEX[axis]
    size = scope.size[index]
    bounds = (0.0, 0.0, scope.size[0], scope.size[1])
    pieces: list[tuple[int, Geometry, Scope]] = []
    last_index = len(intervals) - 1
    for k, (lo, hi) in enumerate(intervals):
        slab = _slab(bounds, index, lo, hi, k == 0 and lo <= 0, k == last_index and hi >= size)
        for polygon in polygons_of(local.intersection(slab)):
            piece, piece_scope = face_from_polygon(polygon, scope, face.kind)
            pieces.append((k, piece, piece_scope))
    return pieces


def cut(shape: Shape, axis: str, intervals: Sequence[tuple[float, float]]
        ) -> list[tuple[int, Geometry, Scope]]:
    """Cut ``shape`` into the slabs ``intervals`` along ``axis``.

    Parameters
    ----------
    shape:
        A mass or a face.
    axis:
        ``"x"``, ``"y"`` or ``"z"`` of the shape's scope.
    intervals:
        ``(start, end)`` offsets from the scope origin along ``axis``, in metres,
        increasing and non-overlapping; an interval's end should be the next one's start
        for the pieces to tile.

    Returns
    -------
    list
        ``(interval_index, geometry, scope)`` for every non-empty piece, in interval
        order; an interval may give several pieces (a footprint falling apart) or none.
    """
    geometry = shape.geometry
    if isinstance(geometry, Mass):
        return _cut_mass(geometry, axis, intervals)
    return _cut_face(geometry, shape.scope, axis, intervals)
