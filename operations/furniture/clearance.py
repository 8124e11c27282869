"""Clearance geometry: the space an item needs and the space doors and windows keep free.

Three kinds of plan regions decide where furniture may stand (docs/furniture.md, thesis §5.3.2):

* an item's **envelope**: its body (the footprint) and its clearance boxes in front,
  behind and at both sides, sized by the rule's ``clearanceFront/Back/Side``. The thesis
  checked clearances by stepping four clones of the item outwards; here they are exact
  rectangles, so a check is one intersection test;
* a door's **keep-out zone**: on the side the leaf swings into, the quarter circle swept
  by the leaf (radius = door width, centred on the hinge at the wall face), covered by
  a few boxes; on the other
  side a door-wide square in front of the opening, so nobody has to climb over furniture
  to reach the handle;
* a window's **strip**: the band in front of the window's span. An item that could cover
  a window (``canCloseWindow``) must stay out of the band as deep as the item itself plus
  its front clearance;
* a door's strip, the same band in front of a door: its shallow part is where a robot
  stands right after coming through the door (:mod:`.passage`).

Items turn in quarter turns only, so every envelope box is axis-aligned; boxes are
returned as ``(minx, minz, maxx, maxz)`` relative to the item's centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import shapely
from shapely.geometry import Point, Polygon

from cga.model import OUTSIDE, FloorPlan, Wall, front_vector

__all__ = [
    "Box",
    "EnvelopePart",
    "envelope",
    "half_extents",
    "Keepout",
    "door_keepouts",
    "face_offset",
    "OpeningStrip",
    "window_strips",
    "door_strips",
    "quarter_turn_towards",
]

Box = tuple[float, float, float, float]
"""An axis-aligned rectangle ``(minx, minz, maxx, maxz)`` in plan coordinates."""

_SWING_STEPS = 4
"""Boxes that cover the quarter circle of a door's swing (:func:`_swing_steps`)."""


@dataclass(frozen=True)
class EnvelopePart:
    """One box of an item's envelope: ``"body"`` or a clearance ``"front"``, ``"back"`` or
    ``"side"``; ``box`` is relative to the item's centre."""

    kind: Literal["body", "front", "back", "side"]
    box: Box

    @property
    def is_body(self) -> bool:
        return self.kind == "body"


def half_extents(width: float, depth: float, rotation: int) -> tuple[float, float]:
    """Half the footprint's extent along x and z for a rotation (odd turns swap them)."""
    return (width / 2, depth / 2) if rotation % 2 == 0 else (depth / 2, width / 2)


def _frame_box(front: tuple[float, float], s0: float, s1: float, f0: float, f1: float) -> Box:
    """The world-aligned box of ``[s0, s1]`` across and ``[f0, f1]`` along ``front``."""
    fx, fz = front
    sx, sz = -fz, fx  # the item's width axis (x at rotation 0)
    xs = [sx * s + fx * f for s in (s0, s1) for f in (f0, f1)]
    zs = [sz * s + fz * f for s in (s0, s1) for f in (f0, f1)]
    return (min(xs), min(zs), max(xs), max(zs))


def envelope(width: float, depth: float, rotation: int, *, front: float = 0.0,
             back: float = 0.0, side: float = 0.0) -> tuple[EnvelopePart, ...]:
    """The body and clearance boxes of an item, relative to its centre.

    Parameters
    ----------
    width, depth:
        The model's footprint (x and z extent at rotation 0), metres.
    rotation:
        Quarter turns about +y; the front faces :func:`cga.model.front_vector`.
    front, back, side:
        Clearances in metres; a zero clearance contributes no box.

    Returns
    -------
    tuple of EnvelopePart
        The body first, then the non-empty clearance boxes. Clearance boxes span the
        body's width (front/back) or depth (sides), not the corners between them.
    """
    f = front_vector(rotation)
    hw, hd = width / 2, depth / 2
    parts = [EnvelopePart("body", _frame_box(f, -hw, hw, -hd, hd))]
    if front > 0:
        parts.append(EnvelopePart("front", _frame_box(f, -hw, hw, hd, hd + front)))
    if back > 0:
        parts.append(EnvelopePart("back", _frame_box(f, -hw, hw, -hd - back, -hd)))
    if side > 0:
        parts.append(EnvelopePart("side", _frame_box(f, hw, hw + side, -hd, hd)))
        parts.append(EnvelopePart("side", _frame_box(f, -hw - side, -hw, -hd, hd)))
    return tuple(parts)


def face_offset(plan: FloorPlan, room_id: int, at: tuple[float, float]) -> float:
    """Distance from a point on a wall line to the free floor of ``room_id``; 0 for
    :data:`OUTSIDE`.

    This is where furniture may start, measured on the room's ``interior`` (corners on
    the micrometre grid) rather than on the wall band (:meth:`Wall.face_offset
    <cga.model.Wall.face_offset>`), so keep-out zones and in-wall items meet the free
    floor that placement tests against exactly.
    """
    if room_id == OUTSIDE:
        return 0.0
    return float(plan.room(room_id).interior.distance(Point(at)))


@dataclass(frozen=True)
class Keepout:
    """A region furniture must not stand in, with the label used in messages."""

    label: str
    polygon: Polygon


def _rect(origin: np.ndarray, u: np.ndarray, v: np.ndarray) -> Polygon:
    """The parallelogram spanned by vectors ``u`` and ``v`` at ``origin`` (made from one
    array: shapely reads a list of small arrays corner by corner, at twice the cost)."""
    return shapely.polygons(np.array([origin, origin + u, origin + u + v, origin + v]))


def door_keepouts(plan: FloorPlan, room_id: int) -> list[Keepout]:
    """The keep-out zones of every door of ``room_id`` that lie in that room.

    In the room the leaf swings into: the quarter circle swept by the leaf, centred on
    the hinge at the wall face. In the room on the other side, and on both sides of a
    bare opening (``Door.leaf`` False): a door-wide square in front of the opening.
    """
    zones = []
    for door in plan.doors:
        if room_id not in door.rooms:
            continue
        wall = plan.wall(door.wall)
        centre = np.asarray(door.position, dtype=float)
        along = wall.direction
        normal = wall.normal_into(room_id)
        face = centre + normal * face_offset(plan, room_id, door.position)
        label = f"door {door.id}"
        if door.leaf and door.swing_room == room_id:
            towards_latch = along if door.hinge == "start" else -along
            hinge = face - towards_latch * door.width / 2
            zones += [Keepout(f"the swing of {label}", step)
                      for step in _swing_steps(hinge, towards_latch, normal, door.width)]
        else:
            start = face - along * door.width / 2
            zones.append(Keepout(f"the way through {label}",
                                 _rect(start, along * door.width, normal * door.width)))
    return zones


def _swing_steps(hinge: np.ndarray, latch: np.ndarray, normal: np.ndarray,
                 width: float) -> list[Polygon]:
    """The quarter circle a leaf ``width`` wide sweeps from ``hinge`` (the closed leaf
    along ``latch``, opening towards ``normal``) covered by :data:`_SWING_STEPS` boxes
    in the door's frame, one per band of the leaf's opening: each reaches as far along
    the wall as the arc does at its band's near edge, so together they hold the whole
    arc and 11 % more floor than it (4 steps: 0.87 w² against π/4 w²).

    Boxes, not the arc's polygon: beside a wall running along an axis they are
    axis-aligned, and the obstacle index tests those by their bounds alone; an arc in
    every room its door swings into cost the furniture solver over 10 % more time."""
    steps = []
    for k in range(_SWING_STEPS):
        near, far = width * k / _SWING_STEPS, width * (k + 1) / _SWING_STEPS
        reach = math.sqrt(width * width - near * near)
        steps.append(_rect(hinge + normal * near, latch * reach, normal * (far - near)))
    return steps


@dataclass(frozen=True)
class OpeningStrip:
    """A door or window seen from one of its rooms: ``start`` is one end of its span on
    the wall line, ``along`` runs over the span (length ``width``), ``normal`` points into
    the room and ``face`` is the wall's thickness on the room side."""

    label: str
    start: tuple[float, float]
    along: tuple[float, float]
    normal: tuple[float, float]
    width: float
    face: float

    def zone(self, depth: float) -> Polygon:
        """The band in front of the opening, ``depth`` metres deep from the wall face."""
        return _rect(np.asarray(self.start), np.asarray(self.along) * self.width,
                     np.asarray(self.normal) * (self.face + depth))


def _strip(plan: FloorPlan, label: str, wall: Wall, position: tuple[float, float],
           width: float, room_id: int) -> OpeningStrip:
    normal = wall.normal_into(room_id)
    start = np.asarray(position) - wall.direction * width / 2
    return OpeningStrip(
        label=label,
        start=(float(start[0]), float(start[1])),
        along=(float(wall.direction[0]), float(wall.direction[1])),
        normal=(float(normal[0]), float(normal[1])),
        width=width,
        face=face_offset(plan, room_id, position),
    )


def window_strips(plan: FloorPlan, room_id: int) -> list[OpeningStrip]:
    """The windows of ``room_id`` as :class:`OpeningStrip` records."""
    return [_strip(plan, f"window {w.id}", plan.wall(w.wall), w.position, w.width, room_id)
            for w in plan.windows if w.room == room_id]


def door_strips(plan: FloorPlan, room_id: int) -> list[OpeningStrip]:
    """The doors of ``room_id`` seen from that room, as :class:`OpeningStrip` records."""
    return [_strip(plan, f"door {d.id}", plan.wall(d.wall), d.position, d.width, room_id)
            for d in plan.doors if room_id in d.rooms]


_FRONTS = np.array([front_vector(r) for r in range(4)])


def quarter_turn_towards(direction: tuple[float, float] | np.ndarray) -> int:
    """The rotation whose front vector is closest to ``direction``."""
    return int(np.argmax(_FRONTS @ np.asarray(direction, dtype=float)))
