"""Envelopes, door keep-out zones and window strips."""

from __future__ import annotations


import numpy as np
import pytest
import shapely
from shapely.geometry import Point, box

from cga.model import front_vector
from cga.operations.furniture.clearance import (
    door_keepouts, envelope, half_extents, quarter_turn_towards, window_strips)


def boxes(parts):
    return {(p.kind, tuple(round(v, 9) for v in p.box)) for p in parts}


def test_envelope_at_rotation_zero_front_is_minus_z():
    parts = envelope(2.0, 1.0, 0, front=0.5, back=0.2, side=0.1)
    assert parts[0].kind == "body" and parts[0].box == pytest.approx((-1, -0.5, 1, 0.5))
    assert boxes(parts[1:]) == {("front", (-1, -1.0, 1, -0.5)), ("back", (-1, 0.5, 1, 0.7)),
                                ("side", (1, -0.5, 1.1, 0.5)), ("side", (-1.1, -0.5, -1, 0.5))}


@pytest.mark.parametrize("rotation", range(4))
def test_front_clearance_lies_along_the_front_vector(rotation):
    body, front = envelope(2.0, 1.0, rotation, front=0.5)
    centre = np.array([(front.box[0] + front.box[2]) / 2, (front.box[1] + front.box[3]) / 2])
    assert centre == pytest.approx(np.array(front_vector(rotation)) * 0.75)
    hx, hz = half_extents(2.0, 1.0, rotation)
    assert body.box == pytest.approx((-hx, -hz, hx, hz))


def test_zero_clearances_add_no_boxes():
    assert [p.kind for p in envelope(1, 1, 3)] == ["body"]


@pytest.mark.parametrize("direction, rotation", [((0, -1), 0), ((-1, 0), 1), ((0, 1), 2),
                                                 ((1, 0), 3), ((0.9, 0.1), 3)])
def test_quarter_turn_towards(direction, rotation):
    assert quarter_turn_towards(direction) == rotation


def test_door_swing_is_covered_by_boxes_in_the_swing_room(room_plan):
    plan = room_plan(5, 4, doors=((0, 0.5, "start"),))
    zones = door_keepouts(plan, 0)
    assert len(zones) == 4 and all("swing of door 0" in z.label for z in zones)
    swing = shapely.union_all([z.polygon for z in zones])
    # hinge at the start-side jamb on the inner face of the 0.2 m wall at z = 0
    hinge = Point(2.05, 0.2)
    arc = hinge.buffer(0.9, quad_segs=64).intersection(box(2.05, 0.2, 2.95, 1.1))
    assert swing.covers(arc.buffer(-1e-9))  # the whole sweep, and not much more
    assert arc.area < swing.area < 1.12 * arc.area
    assert swing.bounds == pytest.approx((2.05, 0.2, 2.95, 1.1), abs=1e-6)
    for zone in zones:  # each an axis-aligned box beside the axis-aligned wall
        assert zone.polygon.area == pytest.approx(box(*zone.polygon.bounds).area)
    assert swing.covers(Point(2.1, 1.0)) and not swing.covers(Point(2.9, 1.05))


def test_door_hinged_at_the_end_mirrors_the_swing(room_plan):
    plan = room_plan(5, 4, doors=((0, 0.5, "end"),))
    swing = shapely.union_all([z.polygon for z in door_keepouts(plan, 0)])
    assert swing.covers(Point(2.9, 1.0)) and not swing.covers(Point(2.1, 1.05))


def test_room_on_the_other_side_keeps_a_square_free(room_plan):
    from dataclasses import replace
    plan = room_plan(5, 4, doors=((0, 0.5, "start"),))
    door = replace(plan.doors[0], swing_room=-1)  # opens outwards: the room keeps a square
    zone = door_keepouts(plan.with_changes(doors=(door,)), 0)[0]
    assert "way through door 0" in zone.label
    assert zone.polygon.symmetric_difference(box(2.05, 0.2, 2.95, 1.1)).area < 1e-9


def test_window_strip_depth(room_plan):
    plan = room_plan(5, 4, doors=(), windows=((2, 0.5),))  # wall 2 runs along z = 4
    (strip,) = window_strips(plan, 0)
    zone = strip.zone(0.5)
    assert zone.bounds == pytest.approx((1.9, 3.3, 3.1, 4.0))
    assert plan.wall(2).normal_into(0) == pytest.approx((0, -1))
