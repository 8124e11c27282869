"""Floor plans from hand-written rectangles (the rule authors' test helper)."""

from __future__ import annotations

import pytest
from shapely.geometry import box

from cga.errors import UsageError
from cga.model import OUTSIDE, FloorSettings
from cga.operations.floorplan import plan_from_rectangles
from dcel_checks import validate_plan


def test_three_rooms_with_a_t_junction():
    plan = plan_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)],
                                index=1, elevation=3.0, height=3.0)
    validate_plan(plan)
    assert (plan.index, plan.elevation, plan.floor_y) == (1, 3.0, 3.2)
    assert [r.area for r in plan.rooms] == [60.0, 40.0, 40.0]
    assert plan.room(0).polygon.equals(box(0, 0, 6, 10))
    # west room: 3 outer sides (0.2 m walls inside) and the inner wall (half of 0.2 m)
    assert plan.room(0).interior.equals(box(0.2, 0.2, 5.9, 9.8))
    assert plan.dcel.adjacency() == {0: [OUTSIDE, 1, 2], 1: [OUTSIDE, 0, 2], 2: [OUTSIDE, 0, 1]}
    inner = sorted((w.rooms, w.start, w.end) for w in plan.walls if not w.outer)
    assert inner == [((0, 1), (6.0, 0.0), (6.0, 5.0)), ((0, 2), (6.0, 5.0), (6.0, 10.0)),
                     ((1, 2), (14.0, 5.0), (6.0, 5.0))]
    assert sum(w.outer for w in plan.walls) == 7
    assert len(plan.windows) == 7  # one per outer wall segment by default


def test_pinwheel_layout_that_no_bsp_makes():
    rects = [(0, 0, 6, 3), (6, 0, 9, 6), (3, 6, 9, 9), (0, 3, 3, 9), (3, 3, 6, 6)]
    plan = plan_from_rectangles(rects)
    validate_plan(plan)
    assert plan.dcel.neighbours(4) == [0, 1, 2, 3]
    assert plan.footprint.equals(box(0, 0, 9, 9))
    assert len(plan.dcel.vertices) == 12


def test_l_shaped_footprint_and_window_counts():
    settings = FloorSettings(windows_per_wall=3, window_width=1.0)
    plan = plan_from_rectangles([(0, 0, 8, 6), (8, 0, 14, 6), (0, 6, 8, 10)], settings=settings)
    validate_plan(plan)
    assert plan.footprint.area == pytest.approx(8 * 6 + 6 * 6 + 8 * 4)
    by_wall = {w.id: [o.center for o in w.openings] for w in plan.walls if w.outer}
    lengths = {w.id: w.length for w in plan.walls}
    for wall_id, centres in by_wall.items():
        # span = length - 0.4; n windows need n * 1.0 + (n + 1) * 0.3 <= span
        expected = min(3, int((lengths[wall_id] - 0.4 - 0.3) // 1.3))
        assert len(centres) == expected, (wall_id, lengths[wall_id])
    south = next(w for w in plan.walls if w.start == (0.0, 0.0))
    assert [o.center for o in south.openings] == pytest.approx([1.85, 4.0, 6.15])  # gaps 1.15 m


@pytest.mark.parametrize("rects, message", [
    ([], "at least one"),
    ([(0, 0, 0, 5)], "empty"),
    ([(0, 0, 0.3, 5)], "too narrow"),
    ([(0, 0, 5, 5), (4, 0, 9, 5)], "overlap"),
    ([(0, 0, 5, 5), (6, 0, 9, 5)], "one connected footprint"),
    ([(0, 0, 5, 5), (5, 5, 9, 9)], "one connected footprint"),
    ([(0, 0, 9, 3), (0, 3, 3, 6), (6, 3, 9, 6), (0, 6, 9, 9)], "hole"),
])
def test_bad_rectangles_raise_usage_errors(rects, message):
    with pytest.raises(UsageError, match=message):
        plan_from_rectangles(rects)


def test_corner_touching_union_is_reported_not_crashed():
    # Two L-shaped halves meeting at a single point enclose nothing but pinch the boundary.
    rects = [(0, 0, 4, 2), (0, 2, 2, 4), (4, 2, 6, 4), (2, 4, 4, 6), (4, 4, 6, 6)]
    with pytest.raises(UsageError):
        plan_from_rectangles(rects)
