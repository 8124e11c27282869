"""The one wall geometry (``Wall.normal``, ``normal_into``, ``band``, ``face_offset``,
``band_corners``), checked against the room polygons and the footprint with shapely probes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon

from cga.model import OUTSIDE, Wall
from cga.operations.floorplan import plan_from_rectangles

PROBE = 1e-3


def _probe(wall: Wall, normal: np.ndarray, offset: float = PROBE) -> Point:
    middle = (np.asarray(wall.start) + np.asarray(wall.end)) / 2
    return Point(*(middle + normal * offset))


def _check_plan(plan) -> None:
    for wall in plan.walls:
        for room in wall.rooms:
            normal = wall.normal_into(room)
            assert np.linalg.norm(normal) == pytest.approx(1.0)
            assert abs(float(normal @ wall.direction)) < 1e-12
            beyond = _probe(wall, normal)
            if room == OUTSIDE:
                assert not plan.footprint.covers(beyond)
            else:
                assert plan.room(room).polygon.covers(beyond)
                if wall.length > 3 * wall.thickness:  # the middle is clear of the joints
                    # the wall's face on this side is where the room's free floor starts
                    face = _probe(wall, normal, wall.face_offset(room))
                    assert plan.room(room).interior.distance(face) < 1e-6
        strip = Polygon(wall.band_corners())
        assert strip.area == pytest.approx(wall.length * wall.thickness)
        assert plan.footprint.buffer(1e-9).covers(strip)
        lo, hi = wall.band()
        assert hi - lo == pytest.approx(wall.thickness)
        if wall.outer:
            assert OUTSIDE in wall.rooms and 0.0 in (lo, hi)
            assert wall.face_offset(OUTSIDE) == 0.0
        else:
            assert lo == -hi


def test_three_rooms():
    plan = plan_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)])
    _check_plan(plan)
    inner = next(w for w in plan.walls if not w.outer)
    a, b = inner.rooms
    assert inner.normal_into(a) == pytest.approx(-inner.normal_into(b))
    assert inner.normal_into(a) == pytest.approx(inner.normal)
    assert inner.band() == pytest.approx((-0.1, 0.1))
    assert inner.face_offset(a) == inner.face_offset(b) == pytest.approx(0.1)


def test_outer_wall_solid_lies_on_its_rooms_side():
    plan = plan_from_rectangles([(0, 0, 4, 3)])
    south = next(w for w in plan.walls if w.start[1] == w.end[1] == 0)
    room = next(r for r in south.rooms if r != OUTSIDE)
    assert south.normal_into(room) == pytest.approx((0.0, 1.0))
    assert south.normal_into(OUTSIDE) == pytest.approx((0.0, -1.0))
    assert south.face_offset(room) == pytest.approx(0.2)
    xs, zs = zip(*south.band_corners())
    assert (min(zs), max(zs)) == pytest.approx((0.0, 0.2))


def test_a_room_not_beside_the_wall_is_an_error():
    plan = plan_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)])
    wall = next(w for w in plan.walls if len(set(w.rooms) - {OUTSIDE}) == 1)
    stranger = next(r.id for r in plan.rooms if r.id not in wall.rooms)
    with pytest.raises(ValueError, match="not beside wall"):
        wall.normal_into(stranger)
    with pytest.raises(ValueError, match="not beside wall"):
        wall.face_offset(stranger)


def test_band_corners_reach_past_the_ends():
    wall = Wall(0, (0.0, 0.0), (2.0, 0.0), False, (0, 1), 0.2)
    corners = wall.band_corners(before=0.1, after=0.3)
    assert corners[:, 0].min() == pytest.approx(-0.1)
    assert corners[:, 0].max() == pytest.approx(2.3)
    assert sorted(set(np.round(corners[:, 1], 9))) == pytest.approx([-0.1, 0.1])


@settings(max_examples=25, deadline=None)
@given(width=st.floats(6, 16), depth=st.floats(5, 12), cut=st.floats(0.3, 0.7),
       left=st.floats(0.3, 0.7), right=st.floats(0.3, 0.7))
def test_every_wall_of_a_four_room_plan(width, depth, cut, left, right):
    x = round(width * cut, 3)
    zl, zr = round(depth * left, 3), round(depth * right, 3)
    plan = plan_from_rectangles([(0, 0, x, zl), (0, zl, x, depth),
                                 (x, 0, width, zr), (x, zr, width, depth)])
    _check_plan(plan)
