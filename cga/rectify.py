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
    """An outline snapped to the axes: ``worst_deg`` is the largest angle a snapped edge
    was off its axis, ``moved`` the largest distance (m) between old and new outline,
    ``edges`` its walls; ``oblique`` walls were too far off an axis and kept, the
    furthest ``oblique_deg`` off."""

    polygon: Polygon
    worst_deg: float
    moved: float
    edges: int
    oblique: int = 0
    oblique_deg: float = 0.0


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
    """``polygon`` (already turned to its main direction) with every edge within
    ``tolerance_deg`` of an axis on that axis; edges further off (a bay, a chamfered
    corner: ``oblique``) are kept, their ends moved onto the neighbouring walls. None
    when no edge is near an axis or the squared outline would not be a simple polygon.
    Holes are not kept (a lot has none)."""
    ring = _ring(polygon)
    if len(ring) < 3:
        return None
    edges = _edges(ring)
    angles = np.degrees(np.arctan2(edges[:, 1], edges[:, 0]))
    deviation = np.abs((angles + 45.0) % 90.0 - 45.0)
    # per edge: 0 along x, 1 along z, 2 oblique
    kind = np.where(deviation > tolerance_deg, 2, (np.abs(edges[:, 0]) < np.abs(edges[:, 1])) * 1)
    if (kind == 2).all():
        return None
    # start at an edge that begins a run (its predecessor is of another kind, or oblique)
    starts = np.flatnonzero((kind != np.roll(kind, 1)) | (kind == 2))
    if not len(starts):
        return None
    runs: list[list[int]] = []  # edge indices, in order, one run of edges along one axis
    for index in np.roll(np.arange(len(ring)), -int(starts[0])):
        if runs and kind[index] != 2 and kind[runs[-1][-1]] == kind[index]:
            runs[-1].append(int(index))
        else:
            runs.append([int(index)])
    lines = []
    for run in runs:
        axis = kind[run[0]]
        if axis == 2:
            lines.append(math.nan)
            continue
        lengths = [float(np.hypot(*edges[i])) for i in run]
        mids = [float((ring[i] + edges[i] / 2)[1 - axis]) for i in run]
        lines.append(sum(m * w for m, w in zip(mids, lengths)) / sum(lengths))
    corners = []
    for k, run in enumerate(runs):  # the corner where run k - 1 ends and run k begins
        point = ring[run[0]]
        before, after = (k - 1) % len(runs), k
        corners.append(_junction(point, kind[runs[before][0]], lines[before],
                                 kind[run[0]], lines[after]))
    squared = Polygon(corners)
    if not squared.is_valid or squared.area <= 0:
        return None
    moved = float(squared.exterior.hausdorff_distance(Polygon(ring).exterior))
    snapped = deviation[kind != 2]
    return Squared(polygon=squared, worst_deg=float(snapped.max()), moved=moved,
                   edges=len(runs), oblique=int((kind == 2).sum()),
                   oblique_deg=float(deviation.max()))


def _junction(point: np.ndarray, kind_in: int, line_in: float, kind_out: int,
              line_out: float) -> tuple[float, float]:
    """Where a wall of ``kind_in`` (0 along x at z = ``line_in``, 1 along z at x =
    ``line_in``, 2 oblique) meets the next of ``kind_out``: two axis walls meet where
    their lines cross; an oblique wall keeps the outline's corner ``point``, moved onto
    the axis wall beside it."""
    x, z = float(point[0]), float(point[1])
    for kind, line in ((kind_in, line_in), (kind_out, line_out)):
        if kind == 0:
            z = line
        elif kind == 1:
            x = line
    return x, z
