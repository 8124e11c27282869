"""Where a door fits in a wall, where it goes, which way it opens.

A wall is a segment of a wall centre line (inner walls) or of the footprint (outer
walls, whose solid lies inside the footprint). A door leaf needs the opening itself plus
:data:`DOOR_MARGIN` on both sides, clear of the walls standing at the segment's ends and
of every other opening in it:

* at an end, the wall meeting there takes half a thickness if the end is inside the
  floor and a whole thickness if it lies on the footprint (the outer wall's solid lies
  inside the footprint); every end of an outer wall counts as lying on the footprint;
* windows and doors already in the wall are kept :data:`DOOR_MARGIN` away.

The leaf is hinged at the jamb nearer the wall's closer end, so the open leaf rests
along the wall that meets there. It swings out of circulation into the room (a front
door into its room), as doors are hung: open leaves then neither narrow a hall or
corridor nor meet one another across it (with the bigger room taking the swing, a
hall's doors swung into the hall, and those facing each other across 1.5 m met).
Between two rooms, or two circulation spaces, it swings into the bigger one. Either way
it swings into the other room when the quarter circle it sweeps only fits there.

Doors are hung one after another (:func:`place_door`), and a leaf whose sweep would
cross the sweep of a door already hung (two doors in one corner of a room, or a room
door beside the front door) is hung otherwise: from its other jamb, then into the other
room, then at the ends of its stretch of wall or on another wall the two rooms share,
the first way that keeps both sweeps apart (else as :func:`make_door` would hang it).
Two doors whose leaves cannot both open are a trap for a robot and a nuisance for
anybody.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Literal

import numpy as np
import shapely
from shapely.geometry import Polygon

from cga.model import OUTSIDE, Door, FloorPlan, Opening, Room, Wall, Window

__all__ = [
    "DOOR_MARGIN",
    "Interval",
    "door_spans",
    "free_intervals",
    "door_centre",
    "front_door_site",
    "clear_windows",
    "make_door",
    "place_door",
    "door_opening",
    "door_swing",
]

DOOR_MARGIN = 0.1
"""Clear wall (m) kept on both sides of a door opening."""

Interval = tuple[float, float]
"""A stretch of a wall: distances (m) of its ends from the wall's start."""

Hinge = Literal["start", "end"]


def door_spans(plan: FloorPlan) -> dict[int, Interval]:
    """The stretch of every wall where a door opening may lie, ignoring other openings.

    Returns
    -------
    dict[int, tuple[float, float]]
        Wall id → ``(lo, hi)``, distances from the wall's start; ``hi - lo`` is the
        widest door the wall can take (negative when the wall is too short for any).
    """
    t = plan.settings.wall_thickness
    ends = np.array([[w.start, w.end] for w in plan.walls], dtype=float).reshape(-1, 2)
    on_footprint = shapely.distance(plan.footprint.boundary, shapely.points(ends)) < 1e-6
    spans: dict[int, Interval] = {}
    for k, wall in enumerate(plan.walls):
        start_clear = DOOR_MARGIN + (t if wall.outer or on_footprint[2 * k] else t / 2)
        end_clear = DOOR_MARGIN + (t if wall.outer or on_footprint[2 * k + 1] else t / 2)
        spans[wall.id] = (start_clear, wall.length - end_clear)
    return spans


def free_intervals(wall: Wall, span: Interval) -> list[Interval]:
    """``span`` minus the wall's openings, each widened by :data:`DOOR_MARGIN`."""
    intervals = [span]
    for opening in wall.openings:
        lo = opening.center - opening.width / 2 - DOOR_MARGIN
        hi = opening.center + opening.width / 2 + DOOR_MARGIN
        intervals = [piece for a, b in intervals
                     for piece in ((a, min(b, lo)), (max(a, hi), b)) if piece[1] > piece[0]]
    return intervals


def door_centre(interval: Interval, width: float, rng: np.random.Generator,
                position: Literal["center", "random"]) -> float:
    """A door centre (distance from the wall start) inside ``interval``.

    ``"center"`` takes the middle; ``"random"`` draws uniformly among the positions
    that keep the whole opening inside the interval.
    """
    lo, hi = interval[0] + width / 2, interval[1] - width / 2
    if position == "center" or hi <= lo:
        return (interval[0] + interval[1]) / 2
    return float(rng.uniform(lo, hi))


def front_door_site(candidates: Sequence[tuple[Wall, Interval]], width: float,
                    rng: np.random.Generator,
                    position: Literal["center", "random"]) -> tuple[Wall, float, bool]:
    """Where the front door goes among a room's outer walls.

    Parameters
    ----------
    candidates:
        The room's outer walls with their door spans, longest span first (at least one,
        whose span takes the door).
    width:
        The door width.
    rng, position:
        As for :func:`door_centre`.

    Returns
    -------
    (wall, centre, replaces_windows)
        In the longest stretch free of windows that takes the door. When there is none,
        the door takes a window's place (third item True; see :func:`clear_windows`):
        centred on the window whose replacement removes the fewest windows, preferring
        the longer wall and the window nearer the middle of its wall.
    """
    best: tuple[Wall, Interval] | None = None
    for wall, span in candidates:
        for lo, hi in free_intervals(wall, span):
            if hi - lo >= width - 1e-9 and (best is None or hi - lo > best[1][1] - best[1][0]):
                best = (wall, (lo, hi))
    if best is not None:
        return best[0], door_centre(best[1], width, rng, position), False
    options = []
    for rank, (wall, (lo, hi)) in enumerate(candidates):
        middle = (lo + hi) / 2
        for opening in wall.openings:
            centre = min(max(opening.center, lo + width / 2), hi - width / 2)
            removed = sum(_overlaps(o, centre - width / 2, centre + width / 2)
                          for o in wall.openings)
            options.append((removed, rank, abs(centre - middle), wall, centre))
    _, _, _, wall, centre = min(options, key=lambda option: option[:3])
    return wall, centre, True


def _overlaps(opening: Opening, lo: float, hi: float) -> bool:
    """Whether ``opening`` comes within :data:`DOOR_MARGIN` of ``[lo, hi]``."""
    half = opening.width / 2
    return opening.center - half < hi + DOOR_MARGIN and opening.center + half > lo - DOOR_MARGIN


def clear_windows(wall: Wall, windows: Sequence[Window], lo: float,
                  hi: float) -> tuple[Wall, tuple[Window, ...], tuple[Window, ...]]:
    """Remove the windows of ``wall`` that come within :data:`DOOR_MARGIN` of ``[lo, hi]``.

    Returns
    -------
    (wall, kept, removed)
        The wall without those window openings, and the floor's window records split
        into those kept and those removed.
    """
    openings = tuple(o for o in wall.openings if o.kind != "window" or not _overlaps(o, lo, hi))
    removed = tuple(w for w in windows if w.wall == wall.id and _overlaps(
        Opening("window", math.dist(wall.start, w.position), w.width, w.height), lo, hi))
    kept = tuple(w for w in windows if w not in removed)
    return replace(wall, openings=openings), kept, removed


def _leaf_frame(wall: Wall, centre: float, width: float, hinge: Literal["start", "end"],
                room: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(pivot, along, normal): the hinge point on the room-side face of the wall, the
    unit vector from the hinge to the other jamb and the unit vector into ``room``
    (``Wall.rooms`` is (left, right) walking from start to end)."""
    pivot, along, normal = _leaf_frame_xy(wall, centre, width, hinge, room)
    return np.array(pivot), np.array(along), np.array(normal)


Vector = tuple[float, float]


def _leaf_frame_xy(wall: Wall, centre: float, width: float, hinge: Literal["start", "end"],
                   room: int) -> tuple[Vector, Vector, Vector]:
    """:func:`_leaf_frame` as tuples, computed as ``Wall.normal_into`` and
    ``Wall.point_at`` do (the same bits, without numpy's cost per call)."""
    offset = wall.face_offset(room)  # raises ValueError for a room on neither side
    dx, dz = wall.unit()
    nx, nz = (-dz, dx) if room == wall.rooms[0] else (dz, -dx)
    jamb = centre - width / 2 if hinge == "start" else centre + width / 2
    along = (dx, dz) if hinge == "start" else (-dx, -dz)
    px, pz = wall.point_at(jamb)
    return (px + nx * offset, pz + nz * offset), along, (nx, nz)


_ARC = np.linspace(0.0, math.pi / 2, 9)
_ARC_COS, _ARC_SIN = np.cos(_ARC)[:, None], np.sin(_ARC)[:, None]


def _swing_polygon(wall: Wall, centre: float, width: float, hinge: Literal["start", "end"],
                   room: int) -> Polygon:
    pivot, along, normal = _leaf_frame(wall, centre, width, hinge, room)
    arc = pivot + width * (_ARC_COS * along + _ARC_SIN * normal)
    return shapely.polygons(np.vstack([pivot, arc]))


def door_swing(door: Door, plan: FloorPlan) -> Polygon:
    """The quarter circle a door leaf sweeps in ``door.swing_room`` (plan coordinates).

    Useful to keep furniture out of a door's way.
    """
    return door_swing_on(door, plan.wall(door.wall))


def make_door(door_id: int, wall: Wall, centre: float, rooms: tuple[int, int],
              plan: FloorPlan, *, reason: Literal["rule", "reachability", "front", "stair"]) -> Door:
    """A door record for an opening centred ``centre`` metres along ``wall``.

    ``rooms`` are the two rooms it joins (the second is :data:`~cga.model.OUTSIDE` for
    the front door, which opens into the first). The hinge is the jamb nearer the
    wall's closer end; the leaf swings out of circulation into the room, else into the
    bigger room, unless its sweep only fits the other one (module notes).
    """
    settings = plan.settings
    hinge: Literal["start", "end"] = "start" if centre <= wall.length / 2 else "end"
    if OUTSIDE in rooms:
        swing_room = rooms[0] if rooms[1] == OUTSIDE else rooms[1]
    else:
        preferred = sorted((plan.room(r) for r in rooms),
                           key=lambda r: (r.circulation, -r.area, r.id))
        swing_room = next((r.id for r in preferred if _sweep_fits(
            r, wall, centre, settings.door_width, hinge)),
            preferred[0].id)
    return Door(id=door_id, wall=wall.id, rooms=rooms, position=wall.point_at(centre),
                width=settings.door_width, height=settings.door_height,
                swing_room=swing_room, hinge=hinge, is_front=reason == "front",
                reason=reason)


_SWEEP_OVERLAP = 1e-3
"""Area (m²) two door sweeps may share and still count as apart (touching edges)."""


def place_door(door_id: int, sites: Sequence[tuple[Wall, float]], rooms: tuple[int, int],
               plan: FloorPlan, *, reason: Literal["rule", "reachability", "front", "stair"],
               avoid: Sequence[Polygon] = ()) -> tuple[Door, Polygon]:
    """The door :func:`make_door` hangs at the first of ``sites`` (wall, centre), unless
    its sweep crosses one of ``avoid`` (the sweeps of the doors already hung): then the
    first way, in the order of the module notes, whose sweep fits its room and crosses
    none of them. Returns the door and its sweep."""
    first = make_door(door_id, sites[0][0], sites[0][1], rooms, plan, reason=reason)
    first_sweep = door_swing_on(first, sites[0][0])
    if _sweep_clear(first_sweep, avoid):
        return first, first_sweep
    swing_rooms = ([first.swing_room] if OUTSIDE in rooms else
                   [first.swing_room, rooms[0] if rooms[1] == first.swing_room else rooms[1]])
    for wall, centre in sites:
        hinges: tuple[Hinge, Hinge] = (("start", "end") if centre <= wall.length / 2
                                       else ("end", "start"))  # the natural one first
        for room in swing_rooms:
            for hinge in hinges:
                if not _sweep_fits(plan.room(room), wall, centre, plan.settings.door_width, hinge):
                    continue
                sweep = _swing_polygon(wall, centre, plan.settings.door_width, hinge, room)
                if _sweep_clear(sweep, avoid):
                    return replace(first, wall=wall.id, position=wall.point_at(centre),
                                   swing_room=room, hinge=hinge), sweep
    return first, first_sweep


def door_swing_on(door: Door, wall: Wall) -> Polygon:
    """:func:`door_swing` for a door in ``wall`` (a plan's walls need not hold it yet)."""
    return _swing_polygon(wall, math.dist(wall.start, door.position), door.width,
                          door.hinge, door.swing_room)


def _sweep_clear(sweep: Polygon, others: Sequence[Polygon]) -> bool:
    if not others:
        return True
    met = np.asarray(others, dtype=object)[shapely.intersects(sweep, others)]
    return not (met.size and shapely.area(shapely.intersection(sweep, met)).max() > _SWEEP_OVERLAP)


def _sweep_fits(room: Room, wall: Wall, centre: float, width: float,
                hinge: Literal["start", "end"]) -> bool:
    """Whether the square the leaf sweeps (the quarter circle's bounding square, a hair
    smaller so the face it starts from counts as inside) lies in the room's free floor."""
    (px, pz), (ax, az), (nx, nz) = _leaf_frame_xy(wall, centre, width, hinge, room.id)
    eps = 1e-6
    cx, cz = px + (ax + nx) * eps, pz + (az + nz) * eps
    reach = width - 2 * eps
    square = [(cx, cz), (cx + ax * reach, cz + az * reach),
              (cx + (ax + nx) * reach, cz + (az + nz) * reach), (cx + nx * reach, cz + nz * reach)]
    box = _axis_aligned_box(room.interior)
    if box is None:
        return room.interior.covers(Polygon(square))
    x0, z0, x1, z1 = box  # a rectangle covers a polygon when it holds its corners
    return all(x0 <= x <= x1 and z0 <= z <= z1 for x, z in square)


def _axis_aligned_box(polygon: Polygon) -> tuple[float, float, float, float] | None:
    """``(minx, minz, maxx, maxz)`` when ``polygon`` is an axis-aligned rectangle
    without holes (most room interiors), else None."""
    if polygon.interiors:
        return None
    ring = polygon.exterior.coords
    if len(ring) != 5:
        return None
    xs, zs = {x for x, _ in ring}, {z for _, z in ring}
    if len(xs) != 2 or len(zs) != 2:
        return None
    return min(xs), min(zs), max(xs), max(zs)


def door_opening(door: Door, plan: FloorPlan) -> Opening:
    """The :class:`~cga.model.Opening` cut into the door's wall."""
    wall = plan.wall(door.wall)
    return Opening(kind="door", center=math.dist(wall.start, door.position),
                   width=door.width, height=door.height)
