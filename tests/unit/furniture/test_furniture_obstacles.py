"""The indexed layout queries give the brute-force answers.

:class:`~cga.operations.furniture.layout.Layout` answers "what blocks this pose" and "where
along this line is nothing in the way" from an STRtree and numpy columns, with a plain
loop for few hits. Here random layouts are checked against an independent brute force:
every obstacle of the room built from the envelope and tested with shapely one by one,
by the blocking table of docs/furniture.md.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon, box
from shapely.ops import unary_union

import cga.operations.furniture.layout as layout_module
from cga.operations.furniture.clearance import Keepout, OpeningStrip, envelope
from cga.operations.furniture.layout import EPS, ItemSpec, Layout, Pose
from cga.operations.furniture.obstacles import ObstacleIndex, complement
from cga.operations.furniture.rules import FurnitureRule

ROOMS = [box(0, 0, 6, 5), unary_union([box(0, 0, 6, 3), box(0, 3, 3, 6)])]
DOOR = Keepout("the swing of door 1", Point(1, 0).buffer(0.9).intersection(box(1, 0, 2, 1)))
WINDOW = OpeningStrip("window 2", (4.0, 0.0), (1.0, 0.0), (0.0, 1.0), 1.2, 0.0)


def _spec(name: str, w: float, d: float, *, front: float = 0.0, side: float = 0.0,
          rug: bool = False, window: bool = False, parent: str | None = None) -> ItemSpec:
    rule = FurnitureRule(room="Livingroom", name=name, clearance_front=front,
                         clearance_side=side, non_collision=rug,
                         can_close_window=window and not rug,  # (a rug covers no window)
                         pair_with=parent, has_pair=parent is not None)
    return ItemSpec(rule, name, (w, 1.0, d))


def _parts(spec: ItemSpec, pose: Pose) -> list[tuple[bool, Polygon]]:
    """(is body, shape shrunk by EPS) of each envelope box, built afresh."""
    r = spec.rule
    out = []
    for part in envelope(spec.width, spec.depth, pose.rotation % 4, front=r.clearance_front,
                         back=r.clearance_back, side=r.clearance_side):
        b = part.box
        out.append((part.kind == "body", box(pose.x + b[0] + EPS, pose.z + b[1] + EPS,
                                             pose.x + b[2] - EPS, pose.z + b[3] - EPS)))
    return out


def brute_blocked(room: Polygon, placed: list[tuple[ItemSpec, Pose]], spec: ItemSpec,
                  pose: Pose, related: frozenset[str], windows: bool) -> bool:
    """Whether anything blocks ``spec`` at ``pose`` (docs/furniture.md), one by one."""
    for is_body, shape in _parts(spec, pose):
        if not shape.within(room):
            return True
        if spec.rule.non_collision:
            continue
        for other, other_pose in placed:
            if other.name == spec.name or other.rule.non_collision:
                continue
            for other_body, other_shape in _parts(other, other_pose):
                if not shape.intersects(other_shape):
                    continue
                if other_body or (is_body and other.name not in related):
                    return True
        if is_body and shape.intersects(DOOR.polygon):
            return True
        if is_body and windows and spec.rule.can_close_window and shape.intersects(
                WINDOW.zone(spec.depth + spec.rule.clearance_front)):
            return True
    return False


item = st.tuples(st.floats(0.3, 1.6), st.floats(0.3, 1.2), st.floats(0, 0.4),
                 st.floats(0, 0.3), st.booleans(), st.booleans(),
                 st.floats(0.2, 5.8), st.floats(0.2, 5.8), st.integers(0, 3))


def _layout(room_index: int, items: list, windows: bool
            ) -> tuple[Layout, list[tuple[ItemSpec, Pose]]]:
    room = ROOMS[room_index]
    layout = Layout(room, [DOOR], [WINDOW] if windows else [])
    placed = []
    for k, (w, d, front, side, rug, window, x, z, rotation) in enumerate(items):
        spec = _spec(f"item{k}", w, d, front=front, side=side, rug=rug and k % 3 == 0,
                     window=window, parent="item0" if k == 1 else None)
        layout.add(spec, Pose(x, z, rotation))
        placed.append((spec, Pose(x, z, rotation)))
    return layout, placed


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 1), st.lists(item, max_size=24), item, st.booleans())
def test_conflicts_agree_with_the_brute_force(room_index, items, candidate, windows):
    layout, placed = _layout(room_index, items, windows)
    spec, pose, related, found = _checked_conflicts(room_index, layout, placed, candidate,
                                                    windows)
    first = layout.conflicts(spec, pose, related, first=True)
    assert first == found[:1]


def _checked_conflicts(room_index, layout, placed, candidate, windows):
    """The conflicts of ``candidate`` in ``layout``, checked against the brute force:
    ``(spec, pose, related, conflicts)``."""
    w, d, front, side, rug, window, x, z, rotation = candidate
    spec = _spec("new", w, d, front=front, side=side, rug=rug, window=window)
    related = frozenset({"item1"}) if len(placed) > 1 else frozenset()
    pose = Pose(x, z, rotation)
    found = layout.conflicts(spec, pose, related)
    assert bool(found) == brute_blocked(ROOMS[room_index], placed, spec, pose, related,
                                        windows)
    return spec, pose, related, found


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 1), st.lists(item, max_size=24), item, st.integers(0, 1),
       st.booleans(), st.randoms(use_true_random=False))
def test_free_intervals_agree_with_the_brute_force(room_index, items, candidate, axis,
                                                   windows, random):
    layout, placed = _layout(room_index, items, windows)
    w, d, front, side, rug, window, x, z, rotation = candidate
    spec = _spec("new", w, d, front=front, side=side, rug=rug, window=window)
    fixed = z if axis == 0 else x
    intervals = layout.free_intervals(spec, rotation, axis, fixed, 0.0, 6.0)
    assert all(a <= b for a, b in intervals)
    assert all(b1 < a2 for (_, b1), (a2, _) in zip(intervals, intervals[1:]))
    for _ in range(40):
        value = random.uniform(0.0, 6.0)
        if any(abs(value - end) < 1e-6 for iv in intervals for end in iv):
            continue  # at an interval's end the two answers differ by rounding only
        pose = Pose(value, fixed, rotation) if axis == 0 else Pose(fixed, value, rotation)
        free = any(a <= value <= b for a, b in intervals)
        assert free == (not brute_blocked(ROOMS[room_index], placed, spec, pose,
                                          frozenset(), windows))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 1), st.lists(item, min_size=1, max_size=30), item, st.integers(0, 1),
       st.booleans())
def test_the_loop_for_few_hits_and_numpy_for_many_agree(room_index, items, candidate, axis,
                                                        windows):
    w, d, front, side, rug, window, x, z, rotation = candidate
    spec = _spec("new", w, d, front=front, side=side, rug=rug, window=window)
    related = frozenset({"item1"})
    answers = []
    for few in (0, 10_000):  # numpy only, then the loop only
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(layout_module, "_FEW_HITS", few)
            layout, _ = _layout(room_index, items, windows)
            fixed = z if axis == 0 else x
            answers.append((layout.conflicts(spec, Pose(x, z, rotation), related),
                            layout.free_intervals(spec, rotation, axis, fixed, 0.0, 6.0,
                                                  related)))
    assert answers[0] == answers[1]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(-2, 8), st.floats(0, 3)), max_size=40),
       st.floats(-1, 4), st.floats(0, 6))
def test_complement_is_the_plain_sweep(intervals, lo, length):
    forbidden = [(a, a + size) for a, size in intervals if size > 0]
    hi = lo + length
    starts = np.array([a for a, _ in forbidden], dtype=float)
    ends = np.array([b for _, b in forbidden], dtype=float)
    expected = layout_module._complement_few(forbidden, lo, hi)
    assert complement(starts, ends, lo, hi) == expected
    for value in np.linspace(lo, hi, 50):  # and the sweep is right
        inside = any(a < value < b for a, b in forbidden)
        if not any(abs(value - e) < 1e-9 for iv in forbidden for e in iv):
            assert any(a <= value <= b for a, b in expected) == (not inside)


def test_a_strip_along_a_crowded_row_finds_every_gap():
    layout = Layout(box(0, 0, 20, 2))
    for k in range(40):  # 0.3 m wide items every 0.5 m leave 0.2 m gaps
        layout.add(_spec(f"b{k}", 0.3, 0.3), Pose(0.25 + 0.5 * k, 1.0, 0))
    intervals = layout.free_intervals(_spec("new", 0.2, 0.2), 0, 0, 1.0, 0.1, 19.9)
    assert len(intervals) == 39 > layout_module._FEW_HITS  # numpy's part
    for k, (a, b) in enumerate(intervals):  # a 0.2 m item fits each gap exactly
        assert a == pytest.approx(0.5 + 0.5 * k, abs=1e-5) and b == pytest.approx(a, abs=1e-5)


pose_pool = st.tuples(st.integers(0, 5), st.sampled_from([0.5, 1.25, 2.0, 3.1, 4.75]),
                      st.sampled_from([0.5, 1.0, 2.5, 3.3]))


@settings(max_examples=60, deadline=None)
@given(st.lists(pose_pool, min_size=1, max_size=30), st.floats(0.3, 1.6), st.floats(0.3, 1.2),
       st.floats(0, 0.4), st.floats(0, 0.3))
def test_the_parts_kept_per_pose_are_those_made_afresh(poses, w, d, front, side):
    spec = _spec("item", w, d, front=front, side=side)
    for rotation, x, z in poses:  # few poses: most asked again
        parts = spec.parts_at(rotation, x, z)
        b = spec.boxes(rotation) + np.array([x + EPS, z + EPS, x - EPS, z - EPS])
        fresh = shapely.box(b[:, 0], b[:, 1], b[:, 2], b[:, 3])
        assert shapely.equals_exact(parts.shapes, fresh, tolerance=0).all()
        assert np.array_equal(parts.bounds, shapely.bounds(fresh))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 1), st.lists(item, min_size=2, max_size=16), item, st.booleans(),
       st.randoms(use_true_random=False))
def test_items_taken_out_and_put_back_block_as_before(room_index, items, candidate, windows,
                                                     random):
    """Adding an item at a pose it stood at before reuses its obstacles."""
    layout, placed = _layout(room_index, items, windows)
    moved = random.sample(placed, random.randint(1, len(placed)))
    for spec, _ in moved:
        layout.remove(spec.name)
    for spec, pose in moved:  # back in another order: the same poses, new rows
        layout.add(spec, pose)
    spec, pose, related, found = _checked_conflicts(room_index, layout, placed, candidate,
                                                    windows)
    fresh, _ = _layout(room_index, [], windows)
    for spec_, pose_ in [p for p in placed if p not in moved] + moved:
        fresh.add(spec_, pose_)
    assert found == fresh.conflicts(spec, pose, related)


def test_an_item_kept_at_a_pose_is_owned_by_its_own_name_in_each_layout():
    a, b = _spec("a", 1.0, 1.0), _spec("b", 1.0, 1.0)
    first = Layout(ROOMS[0])
    first.add(a, Pose(3.0, 2.5, 0))
    first.add(b, Pose(4.5, 2.5, 0))
    second = Layout(ROOMS[0])  # the other order: other ids for the same names
    second.add(b, Pose(4.5, 2.5, 0))
    second.add(a, Pose(3.0, 2.5, 0))
    for layout in (first, second):
        assert [c.blocker for c in layout.conflicts(b, Pose(3.2, 2.5, 0))] == ["a"]
        assert [c.blocker for c in layout.conflicts(a, Pose(4.3, 2.5, 0))] == ["b"]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 1), st.lists(item, min_size=2, max_size=6),
       st.lists(st.tuples(st.integers(0, 5), st.integers(0, 2), st.booleans()), max_size=40),
       item, st.integers(0, 1), st.booleans())
def test_a_layout_back_in_an_earlier_state_answers_as_a_fresh_one(room_index, items, steps,
                                                                   candidate, axis, windows):
    """Layouts keep an obstacle index per state, the window strips and every item's
    parts and strips: each answer is the one of a layout built afresh."""
    specs = [_spec(f"item{k}", w, d, front=front, side=side, window=window)
             for k, (w, d, front, side, _, window, *_) in enumerate(items)]
    poses = [[Pose(x + shift, z, rotation) for shift in (0.0, 0.5, -0.5)]
             for *_, x, z, rotation in items]
    layout, _ = _layout(room_index, [], windows)
    w, d, front, side, rug, window, x, z, rotation = candidate
    new = _spec("new", w, d, front=front, side=side, rug=rug, window=window)
    fixed = z if axis == 0 else x
    for k, which, restart in steps:
        k %= len(specs)
        if restart:  # a fresh attempt: the items so far again, in an empty copy
            order = list(layout.placed.values())
            layout = layout.emptied()
            for spec, pose in order:
                layout.add(spec, pose)
        if specs[k].name in layout.placed:
            layout.remove(specs[k].name)
        else:
            layout.add(specs[k], poses[k][which])
        fresh, _ = _layout(room_index, [], windows)
        for spec, pose in layout.placed.values():
            fresh.add(_spec(spec.name, *spec.size[::2], front=spec.rule.clearance_front,
                            side=spec.rule.clearance_side, window=spec.rule.can_close_window),
                      pose)
        for item_spec in (new, specs[0]):
            for related, first in [(frozenset(), True), (frozenset(), False),
                                   (frozenset({"item1"}), False)]:
                assert (layout.conflicts(item_spec, Pose(x, z, rotation), related, first=first)
                        == fresh.conflicts(item_spec, Pose(x, z, rotation), related,
                                           first=first))
            for related in (frozenset(), frozenset({"item1"})):
                assert (layout.free_intervals(item_spec, rotation, axis, fixed, 0.0, 6.0,
                                              related)
                        == fresh.free_intervals(item_spec, rotation, axis, fixed, 0.0, 6.0,
                                                related))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 1), st.sampled_from([0.7, 2.5]),
                          st.sampled_from([0.0, 0.3]), st.sampled_from([4.0, 5.5])),
                min_size=1, max_size=20),
       st.floats(0.3, 1.6), st.floats(0.3, 1.2), st.floats(0, 0.4), st.floats(0, 0.3))
def test_the_strips_kept_per_segment_are_those_made_afresh(segments, w, d, front, side):
    spec = _spec("item", w, d, front=front, side=side)
    for rotation, axis, fixed, lo, hi in segments:  # few segments: most asked again
        strips = spec.strips(rotation, axis, fixed, lo, hi)
        b = spec.boxes(rotation)
        if axis == 0:
            fresh = shapely.box(lo + b[:, 0], fixed + b[:, 1] + EPS, hi + b[:, 2],
                                fixed + b[:, 3] - EPS)
        else:
            fresh = shapely.box(fixed + b[:, 0] + EPS, lo + b[:, 1], fixed + b[:, 2] - EPS,
                                hi + b[:, 3])
        assert shapely.equals_exact(strips.shapes, fresh, tolerance=0).all()
        assert strips.rows == shapely.bounds(fresh).tolist()


def test_each_depth_keeps_its_own_window_strip():
    """The strip an item must leave in front of a window is as deep as the item and its
    front clearance, whichever item the layout was asked about before."""
    deep = _spec("deep", 0.5, 1.0, window=True)
    shallow = _spec("shallow", 0.5, 0.4, window=True)
    for first, then, pose, blocked in [(deep, shallow, Pose(4.6, 0.8, 0), False),
                                       (shallow, deep, Pose(4.6, 1.2, 0), True)]:
        layout = Layout(ROOMS[0], (), [WINDOW])
        assert layout.fits(first, Pose(4.6, 3.0, 0))
        assert layout.emptied().fits(then, pose) is not blocked


def test_the_answers_kept_for_a_state_are_those_of_the_item_asked_about():
    """Items made and dropped one after another (whose ids Python may give again) each
    get their own answers from the same state, and so does an item asked about with and
    without its family."""
    layout = Layout(ROOMS[0])
    table = _spec("table", 1.0, 1.0, front=0.6)
    chair = _spec("chair", 0.4, 0.4, parent="table")
    layout.add(table, Pose(1.0, 4.0, 0))  # its front clearance: z 3.5 .. 2.9
    for related in (frozenset(), frozenset({"table"}), frozenset()):
        blocked = [c.blocker for c in layout.conflicts(chair, Pose(1.0, 3.2, 0), related)]
        assert blocked == ([] if related else ["table"])
        free = layout.free_intervals(chair, 0, 1, 1.0, 0.3, 4.7, related)
        assert free[0][1] == pytest.approx(3.3 if related else 2.7, abs=1e-5)
    layout.add(_spec("post", 0.4, 0.4), Pose(3.0, 2.5, 0))
    widths = [0.5 + 0.2 * (k % 5) for k in range(30)]  # reaching the post from 1.0 m on
    for width in widths:
        blocked = layout.conflicts(_spec("new", width, 0.5), Pose(2.3, 2.5, 0))
        assert bool(blocked) == (width > 1.0), width
    for width in widths:
        free = layout.free_intervals(_spec("new", width, 0.5), 0, 0, 2.5, 0.1, 5.9)
        assert free[0][1] == pytest.approx(2.8 - width / 2, abs=1e-5)


def test_a_strip_from_zero_keeps_the_sign_of_its_start():
    """Strips are kept by their segment's ends, which compare equal for 0.0 and -0.0: an
    item with a side at its centre (of size zero) sweeps a strip from either."""
    flat = _spec("flat", 0.0, 0.5)
    for lo in (0.0, -0.0, 0.0):
        start = flat.strips(0, 0, 2.0, lo, 5.0).rows[0][0]
        assert math.copysign(1.0, start) == math.copysign(1.0, lo)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 1), st.lists(item, min_size=1, max_size=12), st.booleans())
def test_an_index_extended_by_a_block_is_the_index_of_all_blocks(room_index, items, windows):
    layout, _ = _layout(room_index, items, windows)
    blocks = (layout._static, *layout._item_blocks.values())
    if len(blocks) < 2:  # only rugs: nothing to extend by
        return
    base = ObstacleIndex(blocks[:-1])
    extended, fresh = ObstacleIndex(blocks, base), ObstacleIndex(blocks)
    for name in ("columns", "bounds", "is_rectangle", "shaped"):
        assert np.array_equal(getattr(extended, name), getattr(fresh, name), equal_nan=True)
    assert list(extended.geometries) == list(fresh.geometries)
    assert extended.any_shaped == fresh.any_shaped
    probe = shapely.box(*ROOMS[room_index].bounds)
    assert np.array_equal(extended.tree.query(probe), fresh.tree.query(probe))


def test_an_index_is_extended_only_from_the_state_without_its_last_item():
    a, b, c, d = (_spec(name, 0.5, 0.5) for name in "abcd")
    layout = Layout(ROOMS[0])
    layout.add(a, Pose(1.0, 1.0, 0))
    layout.add(b, Pose(3.0, 1.0, 0))
    new = _spec("new", 0.5, 0.5)
    assert layout.fits(new, Pose(5.0, 3.0, 0))  # queried: a, b
    layout.remove("a")
    layout.add(c, Pose(5.0, 1.0, 0))
    layout.add(d, Pose(5.0, 3.0, 0))  # one item more than a, b, but not a, b and one more
    assert layout.fits(new, Pose(1.0, 1.0, 0))
    assert [k.blocker for k in layout.conflicts(new, Pose(5.0, 1.0, 0))] == ["c"]
