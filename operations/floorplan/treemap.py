"""Partitions aimed at given room areas, and the thesis' mid-cut partition (docs/architecture.md).

:func:`partition_to_areas` is a treemap-style BSP (Marson & Musse's squarified treemaps
over the same half-edge cuts as :mod:`.bsp`): the areas wanted are split into two groups
of similar total, the leaf is cut so that each piece's area is proportional to its
group's total, and each piece goes on with its group. A typing table asks for areas
(a 100 m² living room and bedroom on a 400 m² floor of five rooms), and a random cut
position rarely leaves two rooms that big; aiming the cuts does. Cuts keep the rules of
:mod:`.bsp` (least width and area, offsets from corners, access to circulation); a leaf
that cannot be cut has its two smallest areas merged and is tried again (a piece given
more areas than rooms of the least area and width could fill, :func:`most_rooms`, has
the extra merged at once), and the partition reports the shortfall.

:func:`thesis_partition` is Algorithm 8 of the thesis (createBSPTree, §5.1.2): every
split halves a leaf exactly in the middle, across the axis other than the one that made
the leaf, walking the leaves in the order they were made.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from typing import Literal

import numpy as np
from shapely.geometry import Polygon, box

from .bsp import (Cut, FixedFace, Partition, _best_chord, _candidates, _rectangle_window,
                  _Rules, _shortfall)
from .dcel import DCEL, EPS, Face
from .tiling import tile_with_fixed_faces

__all__ = ["most_rooms", "partition_to_areas", "thesis_partition"]

Point = tuple[float, float]
_AXES: dict[str, int] = {"x": 0, "z": 1}
_MAX_CANDIDATES = 24
"""Cut positions tried per grouping and axis, nearest to the aimed one first."""


def partition_to_areas(footprint: Sequence[Point], areas: Sequence[float],
                       rng: np.random.Generator, *, min_width: float = 2.4,
                       min_area: float = 6.0, grid: float = 0.01, min_offset: float = 0.5,
                       fixed: Sequence[FixedFace] = (), min_contact: float = 0.0) -> Partition:
    """Cut the free floor into ``len(areas)`` rooms whose areas follow ``areas``.

    Parameters
    ----------
    footprint, fixed, min_width, min_area, grid, min_offset, min_contact
        As for :func:`.bsp.partition`.
    areas
        The wanted room areas (m², any order; only their proportions matter: each leaf
        is shared among its areas in proportion).
    rng
        Shuffles equal choices (grouping of the areas, axis of near-square leaves).

    Returns
    -------
    Partition
        ``requested`` is ``len(areas)`` rooms (besides fixed ones); ``shortfall`` says why
        fewer were made.

    Notes
    -----
    Each cut tries a few groupings and both axes, O(n) per candidate as in
    :func:`.bsp.partition`.
    """
    if not areas or any(not a > 0 for a in areas):
        raise ValueError("areas must be a non-empty list of positive areas")
    rules = _Rules(min_width, min_area, (0.02, 0.98), grid, min_offset, min_contact)
    fixed = tuple(fixed)
    rings, pieces = tile_with_fixed_faces(footprint, [f.polygon for f in fixed]) if fixed \
        else ([list(footprint)], 1)
    dcel = DCEL.from_polygons(rings)
    circulation = {dcel.faces[i] for i, f in enumerate(fixed) if f.circulation}
    free = dcel.faces[len(fixed):]
    if not free:  # the fixed faces fill the floor (rooms laid out along a corridor)
        return Partition(dcel, (), len(areas) - pieces,
                         _shortfall(dcel, rules, len(fixed), circulation), fixed)
    polygons = [Polygon(dcel.points(f)) for f in free]
    shares = _share(polygons, list(areas), min_width, rng)
    # more areas than a piece holds are merged at once, as failed cuts would one by one
    fits = [most_rooms(polygon.area, min_width, min_area) for polygon in polygons]
    merged = sum(max(0, len(wanted) - k) for wanted, k in zip(shares, fits))
    todo = [(face, _fewer(wanted, k)) for face, wanted, k in zip(free, shares, fits)]
    cuts: list[Cut] = []
    while todo:
        face, wanted = todo.pop(0)
        if len(wanted) < 2:
            continue
        cut = _cut_for(dcel, face, wanted, rng, rules, circulation)
        if cut is None:  # one room fewer: the two smallest areas become one
            merged += 1
            smallest = sorted(wanted)
            todo.append((face, [smallest[0] + smallest[1], *smallest[2:]]))
            continue
        cut_made, first, second = cut
        cuts.append(cut_made)
        todo += [(dcel.faces[cut_made.face], first), (dcel.faces[cut_made.new_face], second)]
    shortfall = None
    if merged:
        shortfall = _shortfall(dcel, rules, len(fixed), circulation)
    return Partition(dcel, tuple(cuts), len(areas) - pieces, shortfall, fixed)


def _share(pieces: list[Polygon], areas: list[float], min_width: float,
           rng: np.random.Generator) -> list[list[float]]:
    """Give each area to a free piece.

    Every piece gets a number of rooms in proportion to its area (largest remainder,
    at least one each when there are enough rooms), so no piece is left with one room
    far larger than asked. Areas are dealt to the piece with the most area left per
    room still to come, among pieces where a room of that area can be ``min_width``
    wide across the piece's depth; areas with the fewest such pieces go first (small
    rooms fit only shallow pieces).
    """
    total = sum(p.area for p in pieces)
    n = len(areas)
    quota = [int(n * p.area / total) for p in pieces]
    if n >= len(pieces):
        quota = [max(q, 1) for q in quota]
    order = sorted(range(len(pieces)), key=lambda k: -(n * pieces[k].area / total - quota[k]))
    for k in order:
        if sum(quota) >= n:
            break
        quota[k] += 1
    while sum(quota) > n:  # the minimum of one each overshot: take from the largest
        k = max(range(len(pieces)), key=lambda k: (quota[k], -k))
        quota[k] -= 1
    left = [p.area for p in pieces]
    depth = [_strip_depth(p) for p in pieces]
    noise = rng.uniform(0, 1e-3, size=len(pieces))
    groups: list[list[float]] = [[] for _ in pieces]
    fits = [[k for k in range(len(pieces)) if a >= min_width * depth[k] * 0.999] for a in areas]
    for i in sorted(range(n), key=lambda i: (len(fits[i]) or len(pieces) + 1, -areas[i], i)):
        open_ = [k for k in range(len(pieces)) if len(groups[k]) < quota[k]]
        options = [k for k in fits[i] if k in open_] or open_ or list(range(len(pieces)))
        k = max(options, key=lambda k: (left[k] / max(quota[k] - len(groups[k]), 1)
                                        / pieces[k].area + noise[k], -k))
        # no room narrower than min_width across the piece: smaller areas grow to that
        area = max(areas[i], min_width * depth[k] * 1.02)
        groups[k].append(area)
        left[k] -= area
    return groups


def _strip_depth(piece: Polygon) -> float:
    """The depth of a strip-like piece (one side at least twice the other: the rooms
    along a corridor); 0 for compact pieces, whose rooms can be cut either way."""
    w, d = piece.bounds[2] - piece.bounds[0], piece.bounds[3] - piece.bounds[1]
    return min(w, d) if max(w, d) >= 2 * min(w, d) else 0.0


def most_rooms(area: float, min_width: float, min_area: float) -> int:
    """The most rooms at least ``min_area`` big and ``min_width`` wide both ways that
    ``area`` m² holds (at least one): more cannot be cut, and aiming at thousands costs
    time quadratic in their number."""
    return max(1, int(area / max(min_area, min_width ** 2, EPS)))


def _fewer(areas: list[float], count: int) -> list[float]:
    """``areas`` with the two smallest merged into one until ``count`` are left."""
    if len(areas) <= count:
        return areas
    heap = list(areas)
    heapq.heapify(heap)
    while len(heap) > count:
        heapq.heappush(heap, heapq.heappop(heap) + heapq.heappop(heap))
    return sorted(heap)


def _groupings(wanted: list[float], rng: np.random.Generator) -> list[tuple[list[float], list[float]]]:
    """Splits of the areas into two groups of similar total, best balanced first."""
    out = []
    for attempt in range(4):
        order = list(rng.permutation(wanted))
        a: list[float] = []
        b: list[float] = []
        total_a = total_b = 0.0  # sum(a), sum(b): the same additions in the same order
        for w in order:
            if total_a <= total_b:
                a.append(float(w))
                total_a += a[-1]
            else:
                b.append(float(w))
                total_b += b[-1]
        if a and b:
            out.append((a, b))
    out.sort(key=lambda g: abs(sum(g[0]) - sum(g[1])))
    return out


def _cut_for(dcel: DCEL, face: Face, wanted: list[float], rng: np.random.Generator,
             rules: _Rules, circulation: set[Face],
             ) -> tuple[Cut, list[float], list[float]] | None:
    ring = dcel.points(face)
    contact = [h.twin.face in circulation for h in dcel.boundary(face)] if circulation else None
    if contact is not None and not (any(contact) and rules.min_contact > 0):
        contact = None
    xs, zs = zip(*ring)
    dx, dz = max(xs) - min(xs), max(zs) - min(zs)
    axes: list[Literal["x", "z"]] = ["x", "z"] if dx >= dz else ["z", "x"]
    if max(dx, dz) < 1.1 * min(dx, dz) and rng.random() < 0.5:
        axes.reverse()
    polygon = Polygon(ring)
    area = polygon.area
    for low, high in _groupings(wanted, rng):
        small = min(sum(low), sum(high))
        # the smaller group gets its own area when the leaf has more than the areas ask
        # for (the larger group takes the rest), else both shrink in proportion
        part = small / area if sum(wanted) < area else small / sum(wanted)
        part *= rng.uniform(0.98, 1.02)
        share = part if sum(low) <= sum(high) else 1 - part
        for axis in axes:
            k = _AXES[axis]
            marks = sorted({p[k] for p in ring})
            if marks[-1] - marks[0] < 2 * rules.min_width:
                continue  # too narrow for two rooms across this axis
            aim = _position_for_share(polygon, k, marks[0], marks[-1], share)
            # keep the aim where both pieces can be min_width wide (exact for rectangles)
            aim = min(max(aim, marks[0] + rules.min_width), marks[-1] - rules.min_width)
            window = _rectangle_window(ring, k, rules, contact)
            if window[0] > window[1]:
                continue  # no position on this axis gives two valid rooms
            for tried, position in enumerate(_candidates(aim, marks, rules)):  # nearest first
                if tried == _MAX_CANDIDATES:
                    break
                if not window[0] <= position <= window[1]:
                    continue  # still counts as tried
                chord = _best_chord(ring, k, position, rules, contact)
                if chord is None:
                    continue
                h = dcel.split_face(face, *chord)
                kept, new = h.face, h.twin.face
                # the group with the larger total goes to the larger piece
                larger, smaller = (low, high) if sum(low) >= sum(high) else (high, low)
                first, second = ((larger, smaller) if dcel.area(kept) >= dcel.area(new)
                                 else (smaller, larger))
                return Cut(kept.id, new.id, axis, position, *chord), first, second
    return None


def _position_for_share(polygon: Polygon, k: int, lo: float, hi: float, share: float) -> float:
    """The line ``coord[k] = c`` leaving ``share`` of the polygon's area below it
    (exact for rectangles; bisection to 1 cm otherwise)."""
    minx, minz, maxx, maxz = polygon.bounds
    total = polygon.area
    if abs(total - (maxx - minx) * (maxz - minz)) <= 1e-9 * max(total, 1.0):
        return lo + share * (hi - lo)
    a, b = lo, hi
    while b - a > 0.01:
        c = (a + b) / 2
        below = polygon.intersection(box(minx - 1, minz - 1, c, maxz + 1) if k == 0
                                     else box(minx - 1, minz - 1, maxx + 1, c)).area
        if below < share * total:
            a = c
        else:
            b = c
    return (a + b) / 2


def thesis_partition(footprint: Sequence[Point], splits: int) -> Partition:
    """The thesis' BSP (Algorithm 8): mid cuts, alternating axes, leaves in creation order.

    The root counts as made by an ``x`` cut, so the first cut runs along ``z = middle``;
    each later split takes, in creation order, the first uncut leaf whose making axis is
    not the axis the previous split used, and cuts it in the middle across the other
    axis (a leaf whose chord there is not a valid cut stays whole, as the thesis' failed
    ``splitLeaf`` does).

    References
    ----------
    Room-generation thesis §5.1.2, Algorithms 8 (createBSPTree), 9 (splitLeaf), 10.
    """
    dcel = DCEL.from_polygon(footprint)
    made_by: list[Literal["x", "z"]] = ["x"]  # per face id: the axis of the cut that made it
    order = [0]  # leaves in creation order
    start: Literal["x", "z"] = "x"
    cuts: list[Cut] = []
    rules = _Rules(EPS, 0.0, (0.5, 0.5), EPS, 0.0)
    for _ in range(splits):
        for leaf in list(order):
            last = made_by[leaf]
            axis: Literal["x", "z"] = "z" if last == "x" else "x"
            if (last == "x" and start != "z") or (last == "z" and start != "x"):
                cut = _mid_cut(dcel, leaf, axis, rules)
                if cut is not None:
                    cuts.append(cut)
                    order.remove(leaf)
                    order += [cut.face, cut.new_face]
                    made_by += [axis]
                    made_by[cut.face] = axis
                    start = axis
                    break
    return Partition(dcel, tuple(cuts), splits,
                     None if len(cuts) == splits else "no leaf left to halve in the thesis' order")


def _mid_cut(dcel: DCEL, leaf: int, axis: Literal["x", "z"], rules: _Rules) -> Cut | None:
    face = dcel.faces[leaf]
    ring = dcel.points(face)
    k = _AXES[axis]
    values = [p[k] for p in ring]
    middle = (min(values) + max(values)) / 2
    chord = _best_chord(ring, k, middle, rules)
    if chord is None or math.dist(*chord) <= EPS:
        return None
    h = dcel.split_face(face, *chord)
    return Cut(h.face.id, h.twin.face.id, axis, middle, *chord)
