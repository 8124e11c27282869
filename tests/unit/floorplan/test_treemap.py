"""Cuts aimed at areas (treemap BSP) and the thesis' mid-cut partition (Algorithm 8)."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Polygon

from cga.operations.floorplan.bsp import FixedFace
from cga.operations.floorplan.treemap import most_rooms, partition_to_areas, thesis_partition
from dcel_checks import validate_dcel

SQUARE = [(0, 0), (20, 0), (20, 20), (0, 20)]


def areas(result):
    return sorted(round(Polygon(result.dcel.points(f)).area, 2) for f in result.dcel.faces)


def test_thesis_partition_halves_in_the_middle_with_alternating_axes():
    result = thesis_partition(SQUARE, 4)
    validate_dcel(result.dcel, Polygon(SQUARE))
    assert [(c.axis, c.position) for c in result.cuts] == [
        ("z", 10.0), ("x", 10.0), ("z", 15.0), ("x", 10.0)]
    assert areas(result) == [50, 50, 100, 100, 100]
    assert result.shortfall is None


@pytest.mark.parametrize("seed", range(20))
def test_areas_aimed_at_are_met_in_proportion(seed):
    wanted = [150, 40, 150, 40, 20]
    result = partition_to_areas(SQUARE, wanted, np.random.default_rng(seed), min_width=2.4,
                                min_area=4)
    validate_dcel(result.dcel, Polygon(SQUARE))
    got = areas(result)
    assert len(got) == 5 and result.shortfall is None
    for want, have in zip(sorted(wanted), got):
        assert abs(have - want) <= 0.25 * want + 2  # a 1 cm grid and corner offsets


def test_aimed_cuts_keep_corridor_access():
    corridor = FixedFace(((0, 9), (20, 9), (20, 11), (0, 11)), circulation=True)
    result = partition_to_areas(SQUARE, [40, 30, 20, 20, 60, 30, 20, 20],
                                np.random.default_rng(1), min_width=2.0, min_area=4,
                                fixed=[corridor], min_contact=1.5)
    validate_dcel(result.dcel, Polygon(SQUARE))
    hall = Polygon(result.dcel.points(result.dcel.faces[0]))
    assert len(result.dcel.faces) == 9
    for face in result.dcel.faces[1:]:
        room = Polygon(result.dcel.points(face))
        assert room.boundary.intersection(hall.boundary).length >= 1.5 - 1e-9


def test_leaves_that_cannot_be_cut_are_reported():
    result = partition_to_areas([(0, 0), (5, 0), (5, 3), (0, 3)], [5, 5, 5], np.random.default_rng(0),
                                min_width=2.4, min_area=4)
    assert len(result.dcel.faces) == 2 and result.shortfall is not None


def test_fixed_faces_that_fill_the_floor_leave_nothing_to_cut():
    """Rooms laid out along a corridor (n_left, n_right) fill the floor: a re-draw has no
    free piece to cut and says so instead of failing."""
    corridor = FixedFace(((0, 9), (20, 9), (20, 11), (0, 11)), circulation=True)
    below = FixedFace(((0, 0), (20, 0), (20, 9), (0, 9)))
    above = FixedFace(((0, 11), (20, 11), (20, 20), (0, 20)))
    result = partition_to_areas(SQUARE, [60, 60, 60], np.random.default_rng(0), min_width=2.0,
                                min_area=4, fixed=[corridor, below, above], min_contact=1.5)
    validate_dcel(result.dcel, Polygon(SQUARE))
    assert len(result.dcel.faces) == 3 and not result.cuts
    assert result.shortfall == "the fixed faces leave no free floor to cut"


def test_more_areas_than_the_floor_holds_are_merged_up_front():
    """A grammar asking for 10,000 rooms (``split = 10000``) made the re-draws aim at
    10,000 areas, and each leaf that could not be cut merged two of them and tried
    again: minutes for one floor. No more rooms than the floor holds are aimed at, and
    the shortfall is still reported."""
    holds = most_rooms(400.0, 2.4, 4.0)
    assert holds == int(400 / 2.4 ** 2) == 69
    assert most_rooms(3.0, 2.4, 4.0) == 1 and most_rooms(400.0, 1.0, 8.0) == 50
    result = partition_to_areas(SQUARE, [0.04] * 10_000, np.random.default_rng(0),
                                min_width=2.4, min_area=4)
    validate_dcel(result.dcel, Polygon(SQUARE))
    assert 1 < len(result.dcel.faces) <= holds
    assert result.shortfall is not None
    assert all(Polygon(result.dcel.points(f)).area >= 4 - 1e-9 for f in result.dcel.faces)
