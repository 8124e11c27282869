"""Door states: how a build leaves each door leaf (closed, open or ajar; docs/outputs.md).

A robot world needs doors a planner must open as well as doors it can drive through.
``type_rooms(..., door_state=...)`` sets every door of a floor to one state, or draws one
per door from the floor's random stream (``"random"``), so the same seed gives the same
doors. An ajar leaf stands between :data:`AJAR_RANGE` when drawn, at :data:`AJAR_ANGLE`
when asked for; an open leaf at :data:`~cga.model.DOOR_OPEN_ANGLE`.

Two doors hinged near one corner cannot both stand open: their leaves would pass through
each other, or one would stand across the other's doorway, and a robot would find the
way shut by a door the build calls open. :func:`clear_leaves` turns such a leaf back,
in steps, until it is clear (door by door in id order, so earlier doors keep theirs).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from shapely.geometry import Polygon

from cga.model import DOOR_OPEN_ANGLE, DOOR_STATES, Door, DoorState, FloorPlan

__all__ = ["AJAR_ANGLE", "AJAR_RANGE", "DOOR_STATE_CHOICES", "DOORWAY_DEPTH", "clear_leaves",
           "with_door_states"]

AJAR_ANGLE = math.radians(30.0)
"""rad: the angle of a leaf built ``"ajar"``."""

AJAR_RANGE = (math.radians(15.0), math.radians(45.0))
"""rad: the angles a randomly ajar leaf is drawn from (uniform)."""

DOOR_STATE_CHOICES = (*DOOR_STATES, "random")
"""Values of ``type_rooms``' ``door_state``."""

DOORWAY_DEPTH = 0.3
"""m: how far in front of a doorway, on both sides of its wall, another door's leaf may
not stand (half the furniture's passage width: a robot's half-width and margin)."""

LEAF_SPACING = 0.6
"""m: the least gap between two leaves left open (the furniture's passage width), so
two leaves do not close a corridor between them."""

_LEAF_THICKNESS = 0.05
"""m: the leaf a state is judged with (thicker than the shipped door's slab)."""

_TURN_BACK = math.radians(15.0)
"""rad: the step a blocked leaf is turned back by, towards closed."""


def with_door_states(doors: Sequence[Door], state: str, rng: np.random.Generator) -> list[Door]:
    """``doors`` with their ``state`` and ``angle`` set.

    Parameters
    ----------
    doors:
        The floor's doors, in id order.
    state:
        One of :data:`DOOR_STATE_CHOICES`; ``"random"`` draws a state per door (each
        equally likely) and an angle for ajar ones.
    rng:
        The floor's random stream; only ``"random"`` draws from it, so a build with a
        fixed state keeps every other random choice of the floor.

    Raises
    ------
    ValueError
        ``state`` is not one of :data:`DOOR_STATE_CHOICES`.

    Examples
    --------
    >>> from cga.model import Door
    >>> door = Door(0, 3, (0, 1), (1.0, 0.0), 0.9, 2.1, swing_room=1)
    >>> [(d.state, round(d.angle, 4)) for d in with_door_states([door], "open", None)]
    [('open', 1.5708)]
    """
    if state not in DOOR_STATE_CHOICES:
        raise ValueError(f"door_state must be one of {DOOR_STATE_CHOICES}, got {state!r}")
    out = []
    for door in doors:
        angle = None
        if state == "random":
            chosen = DOOR_STATES[int(rng.integers(len(DOOR_STATES)))]
            if chosen == "ajar":
                angle = float(rng.uniform(*AJAR_RANGE))
        else:
            chosen = next(s for s in DOOR_STATES if s == state)  # checked above
        if angle is None:
            angle = {"closed": 0.0, "open": DOOR_OPEN_ANGLE, "ajar": AJAR_ANGLE}[chosen]
        out.append(replace(door, state=chosen, angle=angle))
    return out


def clear_leaves(plan: FloorPlan, doors: Sequence[Door]) -> tuple[list[Door], list[str]]:
    """``doors`` with every leaf that would come within :data:`LEAF_SPACING` of an
    earlier door's leaf, or stand within :data:`DOORWAY_DEPTH` of another doorway,
    turned back by :data:`_TURN_BACK` steps until it is clear (``"ajar"`` below open,
    ``"closed"`` at 0), and a sentence for each one turned back.

    ``plan`` is the typed floor the doors belong to (their walls and rooms). Leaves are
    judged as boxes :data:`_LEAF_THICKNESS` thick (:meth:`cga.doors.DoorLeaf.footprint`);
    closed leaves lie inside their walls and are left as they are.
    """
    from cga.doors import door_leaf

    zones = {door.id: _doorway(plan, door) for door in doors}
    settled: list[Polygon] = []  # the leaves standing open so far, grown by the spacing
    out: list[Door] = []
    notes: list[str] = []
    for door in doors:
        if door.angle <= 0 or not door.leaf:
            out.append(door)
            continue
        leaf = door_leaf(plan, door, _LEAF_THICKNESS)
        others = settled + [zone for k, zone in zones.items() if k != door.id]
        angle = door.angle
        while angle > 0:
            shadow = leaf.footprint(angle)
            if not any(shadow.intersects(other) for other in others):
                break
            angle = max(0.0, angle - _TURN_BACK)
        if angle != door.angle:
            state: DoorState = ("closed" if angle == 0 else
                                "open" if angle >= DOOR_OPEN_ANGLE else "ajar")
            notes.append(f"door {door.id} is left {state}"
                         + (f" at {math.degrees(angle):.0f}°" if state == "ajar" else "")
                         + f" instead of {door.state} at {math.degrees(door.angle):.0f}°: "
                         "further open, its leaf would meet another door's leaf or doorway")
            door = replace(door, state=state, angle=angle)
        if angle > 0:  # the loop stopped at a clear angle, ``shadow`` that leaf's
            settled.append(shadow.buffer(LEAF_SPACING, join_style="mitre"))
        out.append(door)
    return out, notes


def _doorway(plan: FloorPlan, door: Door) -> Polygon:
    """The doorway of ``door`` in plan: its opening through the wall, reaching
    :data:`DOORWAY_DEPTH` into the rooms on both sides."""
    wall = plan.wall(door.wall)
    ux, uz = wall.unit()
    nx, nz = -uz, ux
    half_along, half_across = door.width / 2, wall.thickness / 2 + DOORWAY_DEPTH
    x, z = door.position
    return Polygon([(x + ux * a * half_along + nx * b * half_across,
                     z + uz * a * half_along + nz * b * half_across)
                    for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
