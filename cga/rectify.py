"""Squaring near-rectilinear building outlines.

Outlines traced from aerial images (OpenStreetMap and most cadastres) have right angles
that are off by fractions of a degree. ``make_floor`` cuts rooms with axis-aligned
chords (:mod:`cga.operations.floorplan.bsp`), so such an outline is turned to its main
direction (:func:`main_direction`) and each edge snapped onto the nearer axis
(:func:`square`), as building-footprint regularisation does [Zhang et al. 2006, "A
Squaring Method for Building Footprints", ISPRS]: each run of edges along one axis
becomes one straight wall on the length-weighted mean line of the run, and corners
are where consecutive walls meet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from shapely.geometry import Polygon

__all__ = ["SNAP_TOLERANCE_DEG", "Squared", "main_direction", "edge_deviation", "square"]

SNAP_TOLERANCE_DEG = 3.0
"""Largest angle (degrees) by which an edge may leave its axis and still be snapped
onto it. Traced outlines are off by fractions of a degree; a wall that is meant to be
oblique (a bay, a chamfered corner) is off by far more and keeps the outline as drawn."""

_MIN_EDGE = 1e-3
"""Edges shorter than this (metres) are dropped before squaring: repeated points."""


@dataclass(frozen=True)
class Squared:
    """An outline snapped to the axes: ``worst_deg`` is the largest angle an edge was
    off its axis, ``moved`` the largest distance (m) between old and new outline."""

    polygon: Polygon
    worst_deg: float
    moved: float
    edges: int


def _ring(polygon: Polygon) -> np.ndarray:
    """The exterior's distinct corners in order (no closing repeat, no tiny edges)."""
    points = np.asarray(polygon.exterior.coords)[:-1]
    kept = [points[0]]
    for point in points[1:]:
        if np.hypot(*(point - kept[-1])) >= _MIN_EDGE:
            kept.append(point)
    if len(kept) > 1 and np.hypot(*(kept[0] - kept[-1])) < _MIN_EDGE:
        kept.pop()
    return np.asarray(kept)


def _edges(ring: np.ndarray) -> np.ndarray:
    return np.roll(ring, -1, axis=0) - ring


def main_direction(polygon: Polygon) -> float:
    """The outline's main direction in radians, in [-π/4, π/4): the length-weighted
    mean of its edge directions taken modulo 90° (the circular mean of four times each
    angle, so walls at right angles to each other agree)."""
    edges = _edges(_ring(polygon))
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    angles = np.arctan2(edges[:, 1], edges[:, 0])
    direction = math.atan2(float(np.sum(lengths * np.sin(4 * angles))),
                           float(np.sum(lengths * np.cos(4 * angles)))) / 4
    return direction if direction < math.pi / 4 else direction - math.pi / 2


def edge_deviation(polygon: Polygon) -> float:
    """The largest angle (degrees) by which an edge leaves the nearer axis."""
    edges = _edges(_ring(polygon))
    angles = np.degrees(np.arctan2(edges[:, 1], edges[:, 0]))
    return float(np.max(np.abs((angles + 45.0) % 90.0 - 45.0)))


def square(polygon: Polygon, tolerance_deg: float = SNAP_TOLERANCE_DEG) -> Squared | None:
    """``polygon`` (already turned to its main direction) with every edge on an axis,
    or None when an edge is more than ``tolerance_deg`` off its axis or the squared
    outline would not be a simple polygon. Holes are not kept (a lot has none)."""
    ring = _ring(polygon)
    if len(ring) < 4:
        return None
    worst = edge_deviation(Polygon(ring))
    if worst > tolerance_deg:
        return None
    edges = _edges(ring)
    horizontal = np.abs(edges[:, 0]) >= np.abs(edges[:, 1])
    # start at an edge whose predecessor runs along the other axis, so runs do not wrap
    starts = np.flatnonzero(horizontal != np.roll(horizontal, 1))
    if len(starts) < 4 or len(starts) % 2:
        return None
    order = np.roll(np.arange(len(ring)), -int(starts[0]))
    kinds: list[bool] = []  # per run of edges along one axis: horizontal or not
    sums: list[list[float]] = []  # per run: Σ coordinate · length, Σ length
    for index in order:
        along = bool(horizontal[index])
        length = float(np.hypot(*edges[index]))
        mid = ring[index] + edges[index] / 2
        coordinate = float(mid[1] if along else mid[0])
        if kinds and kinds[-1] == along:
            sums[-1][0] += coordinate * length
            sums[-1][1] += length
        else:
            kinds.append(along)
            sums.append([coordinate * length, length])
    lines = [total / weight for total, weight in sums]
    corners = []
    for k, (along, line) in enumerate(zip(kinds, lines)):
        following = lines[(k + 1) % len(lines)]
        corners.append((following, line) if along else (line, following))
    # corner k ends run k; the outline starts with the corner that ends the last run
    squared = Polygon([corners[-1], *corners[:-1]])
    if not squared.is_valid or squared.area <= 0:
        return None
    moved = float(squared.exterior.hausdorff_distance(Polygon(ring).exterior))
    return Squared(polygon=squared, worst_deg=worst, moved=moved, edges=len(lines))
