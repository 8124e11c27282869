"""The layout: what blocks an item, and the exact sweep of free positions."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, box

from cga.operations.furniture.clearance import Keepout, OpeningStrip, envelope
from cga.operations.furniture.layout import ItemSpec, Layout, Pose, nearest_in
from cga.operations.furniture.rules import FurnitureRule

ROOM = box(0, 0, 5, 4)


def spec(name: str, w: float = 1.0, d: float = 0.5, **rule) -> ItemSpec:
    return ItemSpec(FurnitureRule(room="Livingroom", name=name, **rule), name, (w, 1.0, d))


def test_touching_is_allowed_overlap_is_not():
    layout = Layout(ROOM)
    a = spec("a")
    layout.add(a, Pose(1.0, 1.0, 0))
    assert layout.fits(spec("b"), Pose(2.0, 1.0, 0))  # edges touch at x = 1.5
    (conflict,) = layout.conflicts(spec("b"), Pose(1.9, 1.0, 0))
    assert conflict.describe() == "overlaps a"
    assert layout.fits(spec("c"), Pose(0.5, 0.25, 0))  # flush in the corner
    assert layout.conflicts(spec("c"), Pose(0.4, 0.25, 0))[0].describe() == \
        "does not fit between the walls"


def test_clearance_blocks_others_but_not_family():
    layout = Layout(ROOM)
    layout.add(spec("sofa", 2.0, 0.9, clearance_front=0.6), Pose(2.5, 3.55, 0))  # faces −z
    table = spec("table", 1.0, 0.5, pair_with="sofa", has_pair=True)
    pose = Pose(2.5, 2.8, 0)  # in the sofa's front clearance (z 2.5..3.1)
    assert layout.conflicts(table, pose)[0].describe() == "stands in the clearance of sofa"
    assert layout.fits(table, pose, related=frozenset({"sofa"}))
    lamp = spec("lamp", 0.4, 0.4, clearance_side=0.3)
    (conflict,) = layout.conflicts(lamp, Pose(1.3, 3.5, 0))  # side clearance hits the sofa
    assert conflict.describe() == "clearance side blocked by sofa"


def test_door_zones_and_windows():
    door = Keepout("the swing of door 1", Point(1, 0).buffer(0.9).intersection(box(1, 0, 2, 1)))
    window = OpeningStrip("window 2", (2.0, 0.0), (1.0, 0.0), (0.0, 1.0), 1.2, 0.0)
    layout = Layout(ROOM, [door], [window])
    assert layout.conflicts(spec("a"), Pose(1.5, 0.5, 0))[0].describe() == "blocks the swing of door 1"
    shelf = spec("shelf", 1.0, 0.3, can_close_window=True, clearance_front=0.2)
    assert layout.conflicts(shelf, Pose(2.6, 0.15, 2))[0].describe() == "covers window 2"
    assert layout.fits(shelf, Pose(2.6, 0.65, 2))  # beyond the band (0.3 + 0.2 deep)
    assert layout.fits(spec("sofa", 1.0, 0.3), Pose(2.6, 0.15, 2))  # cannot close a window


def test_non_colliding_items_are_only_kept_inside():
    layout = Layout(ROOM)
    layout.add(spec("table"), Pose(2.5, 2.0, 0))
    rug = spec("rug", 2.0, 1.4, non_collision=True)
    assert layout.fits(rug, Pose(2.5, 2.0, 0))
    layout.add(rug, Pose(2.5, 2.0, 0))
    assert layout.fits(spec("chair", 0.4, 0.4), Pose(2.5, 2.6, 0))  # on the rug
    assert not layout.fits(rug, Pose(0.5, 2.0, 0))


def test_free_intervals_match_a_brute_force_scan():
    rng = np.random.default_rng(7)
    door = Keepout("door", Point(3.2, 0).buffer(0.9).intersection(box(3.2, 0, 4.1, 0.9)))
    layout = Layout(ROOM, [door])
    for k in range(6):
        x, z = rng.uniform(0.5, 4.5), rng.uniform(0.5, 3.5)
        item = spec(f"o{k}", 0.6, 0.4, clearance_front=0.3)
        if layout.fits(item, Pose(x, z, int(rng.integers(4)))):
            layout.add(item, Pose(x, z, int(rng.integers(4))))
    mover = spec("m", 0.8, 0.5, clearance_side=0.2, clearance_back=0.1)
    for rotation in range(4):
        for axis, fixed in ((0, 0.9), (0, 2.3), (1, 1.7), (1, 3.6)):
            intervals = layout.free_intervals(mover, rotation, axis, fixed, 0.0, 5.0)
            for t in np.linspace(0.0, 5.0, 1001):
                pose = Pose(t, fixed, rotation) if axis == 0 else Pose(fixed, t, rotation)
                inside = any(lo - 1e-7 <= t <= hi + 1e-7 for lo, hi in intervals)
                near_edge = any(min(abs(t - lo), abs(t - hi)) < 1e-5 for lo, hi in intervals)
                if not near_edge:
                    assert inside == layout.fits(mover, pose), (rotation, axis, fixed, t)


def test_free_interval_can_be_a_single_exact_fit():
    layout = Layout(box(0, 0, 2, 1))
    intervals = layout.free_intervals(spec("bed", 2.0, 1.0), 0, 0, 0.5, 0.0, 2.0)
    assert len(intervals) == 1 and intervals[0] == pytest.approx((1.0, 1.0))


def test_remove_and_nearest_in():
    layout = Layout(ROOM)
    layout.add(spec("a"), Pose(1, 1, 0))
    layout.remove("a")
    assert layout.fits(spec("b"), Pose(1, 1, 0)) and layout.pose("a") is None
    assert nearest_in([(0, 1), (3, 4)], 2.2) == 3
    assert nearest_in([(0, 1), (3, 4)], 0.5) == 0.5
    assert nearest_in([], 1.0) is None


@settings(max_examples=100, deadline=None)
@given(st.floats(0.1, 3.0), st.floats(0.1, 3.0), st.floats(0, 1), st.floats(0, 1),
       st.floats(0, 1), st.integers(0, 7))
def test_the_extent_is_the_box_around_the_parts(w, d, front, back, side, rotation):
    item = spec("item", w, d, clearance_front=front, clearance_back=back,
                clearance_side=side)
    boxes = [p.box for p in envelope(w, d, rotation % 4, front=front, back=back, side=side)]
    assert item.extent(rotation) == (min(b[0] for b in boxes), min(b[1] for b in boxes),
                                     max(b[2] for b in boxes), max(b[3] for b in boxes))
