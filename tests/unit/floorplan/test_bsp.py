"""BSP choices: axis by aspect, cut range, largest leaf first, widths, alignment."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Polygon

from cga.operations.floorplan.bsp import partition
from dcel_checks import narrowest_room_violation, validate_dcel

L_SHAPE = [(0, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)]


def rect(w, d):
    return [(0, 0), (w, 0), (w, d), (0, d)]


def rng(seed=0):
    return np.random.default_rng(seed)


def rooms(result):
    return [Polygon(result.dcel.points(f)) for f in result.dcel.faces]


@pytest.mark.parametrize("footprint, axis", [(rect(10, 4), "x"), (rect(4, 10), "z")])
def test_cut_runs_across_the_longer_side(footprint, axis):
    for seed in range(20):
        result = partition(footprint, 1, rng(seed))
        assert [c.axis for c in result.cuts] == [axis]


def test_near_square_leaves_use_both_axes():
    axes = {partition(rect(10, 9.5), 1, rng(seed)).cuts[0].axis for seed in range(40)}
    assert axes == {"x", "z"}


def test_cut_position_from_cut_range_on_a_1cm_grid():
    positions = [partition(rect(14, 10), 1, rng(seed)).cuts[0].position for seed in range(200)]
    assert min(positions) >= 0.35 * 14 - 1e-9 and max(positions) <= 0.65 * 14 + 1e-9
    assert max(positions) - min(positions) > 0.5 * 0.3 * 14  # really drawn, not the middle
    assert all(abs(p * 100 - round(p * 100)) < 1e-6 for p in positions)
    narrow = [partition(rect(14, 10), 1, rng(seed), cut_range=(0.5, 0.5)).cuts[0].position
              for seed in range(5)]
    assert narrow == [7.0] * 5


def test_largest_leaf_is_cut_first():
    for seed in range(20):
        result = partition(rect(20, 6), 2, rng(seed))
        first, second = result.cuts
        areas_after_first = {first.face: first.position * 6, first.new_face: (20 - first.position) * 6}
        assert second.face == max(areas_after_first, key=areas_after_first.get)


def test_minimum_width_moves_the_cut_and_stops_the_partition():
    # 5.2 m: only positions 2.4–2.8 keep both rooms 2.4 m wide, all outside 35–65 %.
    for seed in range(10):
        result = partition(rect(5.2, 3), 1, rng(seed), cut_range=(0.1, 0.2), min_area=0)
        assert len(result.cuts) == 1 and 2.4 <= result.cuts[0].position <= 2.8
    result = partition(rect(4.7, 3), 1, rng(0), min_area=0)
    assert result.cuts == () and len(result.dcel.faces) == 1
    assert "narrower than 2.40 m" in result.shortfall and "4.70 × 3.00 m" in result.shortfall


def test_minimum_area_is_honoured():
    result = partition(rect(6, 3), 1, rng(0), min_width=1.0, min_area=10.0)
    assert result.cuts == () and "smaller than 10.00 m²" in result.shortfall
    result = partition(rect(14, 10), 30, rng(0), min_area=12.0)
    assert result.shortfall is not None
    assert all(p.area >= 12.0 - 1e-9 for p in rooms(result))
    assert all(min(b[2] - b[0], b[3] - b[1]) >= 2.4 - 1e-9 for b in (p.bounds for p in rooms(result)))


def test_cut_near_a_corner_lines_up_with_it():
    # drawn at 0.56 * 14 = 7.84, within 0.5 m of the L's inner corner x = 8
    result = partition(L_SHAPE, 1, rng(0), cut_range=(0.56, 0.56))
    assert result.cuts[0].position == 8.0
    assert sorted(p.area for p in rooms(result)) == [36.0, 80.0]
    assert all(p.equals(p.envelope) for p in rooms(result))  # two rectangles
    # drawn at 0.52 * 14 = 7.28 would leave a 0.72 m strip beside the inner corner: the
    # nearest valid position is the corner itself; at 0.4 * 14 = 5.6 the drawn one stays
    assert partition(L_SHAPE, 1, rng(0), cut_range=(0.52, 0.52)).cuts[0].position == 8.0
    assert partition(L_SHAPE, 1, rng(0), cut_range=(0.4, 0.4)).cuts[0].position == 5.6


def test_cut_near_a_wall_end_lines_up_with_it():
    # Cuts at the middle: x = 6 (on the corner), the taller east half at z = 5.3, then
    # the west half's cut, drawn at z = 5.0, is 0.3 m from that wall's end and meets it.
    footprint = [(0, 0), (12, 0), (12, 10.6), (6, 10.6), (6, 10), (0, 10)]
    result = partition(footprint, 3, rng(0), cut_range=(0.5, 0.5))
    assert [(c.axis, c.position) for c in result.cuts] == [("x", 6.0), ("z", 5.3), ("z", 5.3)]
    validate_dcel(result.dcel, Polygon(footprint))
    cross = [v for v in result.dcel.vertices if v.point == (6.0, 5.3)]
    assert len(cross) == 1 and len(cross[0].outgoing()) == 4


def test_no_sliver_segments_next_to_wall_ends():
    for seed in range(30):
        result = partition(rect(14, 10), 9, rng(seed))
        for h in result.dcel.half_edges:
            assert h.length >= 0.5 - 1e-9, (seed, h)


def test_concave_leaf_takes_one_chord_of_a_line_crossing_it_twice():
    u_shape = [(0, 0), (10, 0), (10, 14), (6.5, 14), (6.5, 4), (3.5, 4), (3.5, 14), (0, 14)]
    result = partition(u_shape, 1, rng(0))
    cut = result.cuts[0]
    assert cut.axis == "z" and 4.9 <= cut.position <= 9.1
    assert abs(cut.end[0] - cut.start[0]) == 3.5  # across one arm only
    validate_dcel(result.dcel, Polygon(u_shape))
    assert sorted(len(result.dcel.points(f)) for f in result.dcel.faces) == [4, 8]


@pytest.mark.parametrize("footprint", [
    L_SHAPE,
    [(0, 0), (14, 0), (14, 10), (10, 10), (10, 5), (4, 5), (4, 10), (0, 10)],
    [(0, 0), (14, 0), (14, 4), (10, 4), (10, 10), (4, 10), (4, 4), (0, 4)],
])
def test_concave_footprints_give_valid_wide_rooms(footprint):
    for seed in range(10):
        result = partition(footprint, 8, rng(seed))
        validate_dcel(result.dcel, Polygon(footprint))
        for p in rooms(result):
            assert p.area >= 6.0 - 1e-9
            assert narrowest_room_violation(p, 2.4) == 0.0


def test_same_stream_same_layout():
    a = partition(rect(14, 10), 6, rng(5))
    b = partition(rect(14, 10), 6, rng(5))
    c = partition(rect(14, 10), 6, rng(6))
    assert a.cuts == b.cuts and a.cuts != c.cuts


@pytest.mark.parametrize("kwargs", [{"splits": -1}, {"cut_range": (0.7, 0.3)}, {"cut_range": (0.0, 0.5)},
                                    {"min_width": 0.0}])
def test_bad_arguments(kwargs):
    args = {"splits": 2} | kwargs
    splits = args.pop("splits")
    with pytest.raises(ValueError):
        partition(rect(14, 10), splits, rng(), **args)
