"""Open leaves never meet (operations/roomtyping/door_states.py, ``clear_leaves``).

Two doors hinged near one corner cannot both stand open. The leaves are checked here
with plain trigonometry on the door records (hinge at the jamb on the swing side, the
leaf a segment of the door's width turned by its angle into the swing room), not with
:class:`cga.doors.DoorLeaf`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from shapely.geometry import LineString, Point, box

from cga.model import OUTSIDE, Door, FloorPlan, FloorSettings, Room, Wall
from cga.operations.roomtyping.door_states import (DOORWAY_DEPTH, LEAF_SPACING, clear_leaves,
                                                   with_door_states)

T = 0.2  # wall thickness


def corner_room(at: float) -> FloorPlan:
    """A 5 × 4 m room whose two doors stand ``at`` metres from the corner (0, 0), one on
    the wall along x and one on the wall along z, both swinging in and hinged at the
    corner's end."""
    corners = [(0.0, 0.0), (5.0, 0.0), (5.0, 4.0), (0.0, 4.0)]
    walls = tuple(Wall(i, corners[i], corners[(i + 1) % 4], True, (0, OUTSIDE), T)
                  for i in range(4))
    room = Room(0, box(0, 0, 5, 4), box(T / 2, T / 2, 5 - T / 2, 4 - T / 2), "Livingroom")
    doors = (Door(0, 0, (0, OUTSIDE), (at, 0.0), 0.9, 2.1, 0, "start", True, "front"),
             Door(1, 3, (0, OUTSIDE), (0.0, at), 0.9, 2.1, 0, "end"))
    return FloorPlan(0, 0.0, 3.0, box(0, 0, 5, 4), FloorSettings(wall_thickness=T), (room,),
                     walls, doors=doors)


def leaf(plan: FloorPlan, door: Door) -> LineString:
    """The leaf as a segment: from the hinge (the opening's end the ``hinge`` names,
    on the wall face of the swing room) the door's width long, turned by its angle away
    from the wall into the room."""
    wall = plan.wall(door.wall)
    (x0, z0), (x1, z1) = wall.start, wall.end
    length = math.dist(wall.start, wall.end)
    ux, uz = (x1 - x0) / length, (z1 - z0) / length
    if door.hinge == "end":
        ux, uz = -ux, -uz
    inside = plan.room(door.swing_room).interior
    nx, nz = next(n for n in ((-uz, ux), (uz, -ux)) if inside.contains(
        Point(door.position[0] + n[0] * 0.5, door.position[1] + n[1] * 0.5)))
    hx = door.position[0] - ux * door.width / 2 + nx * wall.thickness / 2
    hz = door.position[1] - uz * door.width / 2 + nz * wall.thickness / 2
    c, s = math.cos(door.angle), math.sin(door.angle)
    dx, dz = c * ux + s * nx, c * uz + s * nz
    return LineString([(hx, hz), (hx + dx * door.width, hz + dz * door.width)])


@pytest.mark.parametrize("state", ["open", "ajar"])
def test_a_door_alone_keeps_its_state(state):
    plan = corner_room(2.5)
    doors = with_door_states(plan.doors[:1], state, None)
    assert clear_leaves(plan, doors) == (doors, [])


def test_leaves_at_one_corner_are_turned_back_until_clear():
    plan = corner_room(0.7)
    opened = with_door_states(plan.doors, "open", None)
    assert leaf(plan, opened[0]).distance(leaf(plan, opened[1])) < 0.1  # they would meet
    cleared, notes = clear_leaves(plan, opened)
    first, second = cleared
    assert first.angle < opened[0].angle or second.angle < opened[1].angle
    assert len(notes) == sum(d.angle < math.pi / 2 for d in cleared)
    for door in cleared:
        assert door.state == ("open" if door.angle == math.pi / 2 else
                              "closed" if door.angle == 0 else "ajar")
    if first.angle > 0 and second.angle > 0:
        assert leaf(plan, first).distance(leaf(plan, second)) >= LEAF_SPACING - 0.06


def doorway(plan: FloorPlan, door: Door):
    """The opening of ``door`` through its wall, :data:`DOORWAY_DEPTH` deep into the rooms
    on both sides."""
    wall = plan.wall(door.wall)
    (x0, z0), (x1, z1) = wall.start, wall.end
    length = math.dist(wall.start, wall.end)
    ux, uz = (x1 - x0) / length, (z1 - z0) / length
    along = LineString([(door.position[0] - ux * door.width / 2, door.position[1] - uz * door.width / 2),
                        (door.position[0] + ux * door.width / 2, door.position[1] + uz * door.width / 2)])
    return along.buffer(wall.thickness / 2 + DOORWAY_DEPTH, cap_style="flat")


def test_a_leaf_never_stands_in_another_doorway():
    """Either door opened alone, the other closed: the open one turns back rather than
    stand across the closed one's doorway."""
    plan = corner_room(0.7)
    for door, other in ((0, 1), (1, 0)):
        turned = [replace(d, state="closed", angle=0.0) if d.id == other else
                  replace(d, state="open", angle=math.pi / 2) for d in plan.doors]
        assert leaf(plan, turned[door]).intersects(doorway(plan, turned[other]))
        cleared, notes = clear_leaves(plan, turned)
        assert cleared[other] == turned[other] and len(notes) == 1
        assert not leaf(plan, cleared[door]).intersects(doorway(plan, turned[other]))
