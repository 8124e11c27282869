"""Placement strategies: corners, walls, children around / beside / in front, parents."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, box

from cga.model import FurnitureItem, front_vector
from cga.operations.furniture.clearance import Keepout
from cga.operations.furniture.layout import ItemSpec, Layout, Pose
from cga.operations.furniture.placement import Edge, Placer, convex_corners, room_edges
from cga.operations.furniture.rules import FurnitureRule

ROOM = box(0, 0, 5, 4)


def spec(name: str, size: tuple[float, float], **rule) -> ItemSpec:
    if rule.get("pair_with"):
        rule.setdefault("has_pair", True)
    return ItemSpec(FurnitureRule(room="Livingroom", name=name, **rule), name,
                    (size[0], 1.0, size[1]))


def placer(specs, room=ROOM, keepouts=()) -> Placer:
    return Placer(Layout(room, list(keepouts)), specs, np.random.default_rng(0))


def item(p: Placer, name: str) -> FurnitureItem:
    s, pose = p.layout.placed[name]
    return FurnitureItem(name, s.model, 0, (pose.x, pose.z), pose.rotation, s.size)


def test_room_edges_and_corners_of_an_l_shape():
    from shapely.geometry import Polygon
    room = Polygon([(0, 0), (6, 0), (6, 2), (3, 2), (3, 2.0), (2, 2), (2, 5), (0, 5)])
    edges = room_edges(room)
    assert len(edges) == 6 and all(e.axis is not None for e in edges)
    assert sorted(c.vertex for c in convex_corners(edges)) == [(0, 0), (0, 5), (2, 5), (6, 0), (6, 2)]
    for edge in edges:  # normals point into the room
        mid = np.add(edge.start, edge.end) / 2 + edge.normal * 0.01
        assert room.contains(Point(*mid))


def _numpy_distance(start, end, point) -> float:
    """The distance from ``point`` to the segment, as numpy computes it on 2-vectors."""
    p, a = np.asarray(point, dtype=float), np.asarray(start, dtype=float)
    d = np.subtract(end, start)
    t = np.clip(np.dot(p - a, d) / np.dot(d, d), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * d)))


coordinate = st.one_of(st.floats(-50, 50).filter(lambda v: v == 0 or abs(v) > 1e-6),
                       st.integers(-500, 500).map(lambda k: k / 10))
"""Room coordinates: any float of metres, or on a decimetre grid (no edge so short that
its squared length underflows)."""


@settings(max_examples=500, deadline=None)
@given(st.tuples(coordinate, coordinate, coordinate, coordinate), coordinate, coordinate,
       st.integers(0, 2))
def test_edge_distance_is_the_numpy_distance_to_the_bit(ends, px, pz, aligned):
    """The wall search sorts edges by their distance: plain floats must give numpy's."""
    sx, sz, ex, ez = ends
    ez, ex = (sz, ex) if aligned == 0 else (ez, sx) if aligned == 1 else (ez, ex)
    if (sx, sz) == (ex, ez):
        return
    assert Edge((sx, sz), (ex, ez)).distance_to((px, pz)) == _numpy_distance(
        (sx, sz), (ex, ez), (px, pz))


def test_corner_item_goes_flush_into_the_nearest_corner():
    lamp = spec("lamp", (0.4, 0.3), is_in_corner=True)
    p = placer([lamp])
    assert p.place(lamp, (4.5, 3.6)) is None
    footprint = item(p, "lamp").footprint()
    assert footprint.bounds[2:] == pytest.approx((5.0, 4.0))
    front = np.array(item(p, "lamp").front)
    assert ROOM.contains(Point(*(np.array(item(p, "lamp").position) + front * 0.5)))


def test_corner_item_tries_the_other_orientation_and_the_next_corner():
    wide = spec("wide", (1.2, 0.3), is_in_corner=True, clearance_side=0.2)
    narrow = box(0, 0, 1.3, 3)  # 1.2 + 0.2 side clearance only fits along z
    p = placer([wide], room=narrow)
    assert p.place(wide, (0.1, 0.1)) is None
    assert item(p, "wide").rotation % 2 == 1
    blocker = Keepout("the swing of door 0", box(0, 0, 1.3, 1.5))
    p = placer([wide], room=narrow, keepouts=[blocker])
    assert p.place(wide, (0.1, 0.1)) is None
    assert item(p, "wide").position[1] > 1.5


def test_wall_item_stands_back_to_the_nearest_wall_facing_in():
    shelf = spec("shelf", (1.0, 0.35), is_along_wall=True, clearance_back=0.1)
    p = placer([shelf])
    assert p.place(shelf, (0.6, 2.2)) is None
    placed = item(p, "shelf")
    assert placed.front == pytest.approx((1, 0))  # left wall, facing +x
    assert placed.footprint().bounds[0] == pytest.approx(0.1)  # back clearance to the wall
    assert placed.position[1] == pytest.approx(2.2)  # slid to its start


def test_needs_turn_puts_a_side_against_the_wall():
    bed = spec("bed", (0.9, 2.0), is_along_wall=True, needs_turn=True)
    p = placer([bed])
    assert p.place(bed, (2.5, 0.3)) is None
    placed = item(p, "bed")
    assert placed.footprint().bounds[1] == pytest.approx(0.0)  # long side on the wall z = 0
    assert abs(placed.front[0]) == pytest.approx(1.0)


def test_wall_item_reasons():
    huge = spec("organ", (6.0, 0.5), is_along_wall=True)
    assert placer([huge]).place(huge, (1, 1)) == "no wall long enough for organ (needs 6.00 m)"
    sofa = spec("sofa", (4.0, 0.9), is_along_wall=True)
    p = placer([sofa])
    for k, x in enumerate((0.5, 4.5)):  # posts at both ends of every wall
        for z in (0.5, 3.5):
            post = spec(f"post{k}{z}", (0.2, 0.2))
            p.layout.add(post, Pose(x, z, 0))
    reason = p.place(sofa, (2.5, 0.3))
    assert reason.startswith("no free wall long enough for sofa (4.00 m); nearest wall: overlaps post")


def test_children_around_face_the_parent_and_spread_evenly():
    table = spec("table", (1.6, 0.9), is_along_wall=True, clearance_back=0.3)
    chairs = [spec(f"chair{i}", (0.45, 0.5), pair_with="table", can_be_around=True)
              for i in range(4)]
    p = placer([table, *chairs])
    assert p.place(table, (2.5, 0.2)) is None
    for chair in chairs:
        assert p.place(chair, None) is None
    body = item(p, "table").footprint()
    sides = {}
    for chair in chairs:
        c = item(p, chair.name)
        ray = LineString([c.position, tuple(np.add(c.position, np.array(c.front) * 10))])
        assert ray.intersects(body)
        assert c.footprint().distance(body) == pytest.approx(0.0, abs=1e-9)
        sides.setdefault(c.front, []).append(c)
    assert len(sides) == 3  # front and both ends; the back is 0.3 m off the wall
    front_row = next(group for group in sides.values() if len(group) == 2)
    xs = sorted(c.position[0] for c in front_row)
    assert xs[0] + xs[1] == pytest.approx(2 * item(p, "table").position[0])  # symmetric


def test_children_beside_share_the_parent_orientation_and_back_line():
    bed = spec("bed", (1.6, 2.0), is_along_wall=True)
    stands = [spec(f"stand{i}", (0.45, 0.4), pair_with="bed", is_on_the_side=True)
              for i in range(2)]
    p = placer([bed, *stands])
    assert p.place(bed, (2.5, 0.1)) is None
    for stand in stands:
        assert p.place(stand, None) is None
    b = item(p, "bed")
    for stand in stands:
        s = item(p, stand.name)
        assert s.rotation == b.rotation
        assert s.footprint().bounds[1] == pytest.approx(b.footprint().bounds[1])  # backs aligned
        assert s.footprint().distance(b.footprint()) == pytest.approx(0.0, abs=1e-9)
    assert item(p, "stand0").position[0] != pytest.approx(item(p, "stand1").position[0])
    third = spec("stand2", (0.45, 0.4), pair_with="bed", is_on_the_side=True)
    assert p.place(third, None).startswith("both sides of bed are blocked (overlaps stand")


def test_child_in_front_keeps_its_distance_and_faces_the_parent():
    sofa = spec("sofa", (2.0, 0.9), is_along_wall=True, clearance_front=0.3)
    coffee = spec("coffee", (1.0, 0.6), pair_with="sofa", min_pair_distance=0.3,
                  max_pair_distance=0.5)
    p = placer([sofa, coffee])
    assert p.place(sofa, (2.5, 3.8)) is None
    assert p.place(coffee, None) is None
    s, c = item(p, "sofa"), item(p, "coffee")
    assert c.front == pytest.approx(tuple(-v for v in s.front))
    assert 0.3 - 1e-9 <= c.footprint().distance(s.footprint()) <= 0.5 + 1e-9
    assert c.position[0] == pytest.approx(s.position[0])


def test_wall_child_goes_opposite_and_the_parent_shifts_to_face_it():
    room = box(0, 0, 6, 4)
    sofa = spec("sofa", (2.0, 0.9), is_along_wall=True)
    tv = spec("tv", (1.6, 0.4), pair_with="sofa", is_along_wall=True, min_pair_distance=1.0,
              clearance_side=0.1)
    shelf = spec("shelf", (1.6, 0.4))
    p = placer([sofa, tv, shelf], room=room)
    p.layout.add(shelf, Pose(1.8, 3.8, 0))  # on the top wall, x 1.0 .. 2.6
    p.layout.add(sofa, Pose(3.0, 0.45, 2))  # bottom wall, facing +z
    assert p.place(tv, None) is None
    s, t = item(p, "sofa"), item(p, "tv")
    assert t.footprint().bounds[3] == pytest.approx(4.0)  # against the top wall
    assert t.front == pytest.approx((0, -1))
    assert t.position[0] == pytest.approx(3.5)  # 2.6 + 0.1 clearance + 0.8
    assert s.position[0] == pytest.approx(3.5)  # the sofa moved to face it


def test_parent_look_ahead_picks_a_wall_where_the_children_fit():
    room = box(0, 0, 6, 2.8)  # across the room there is no 1.6 m between sofa and tv
    sofa = spec("sofa", (2.0, 0.9), is_along_wall=True, clearance_side=0.05)
    tv = spec("tv", (1.6, 0.4), pair_with="sofa", is_along_wall=True, min_pair_distance=1.6)
    p = placer([sofa, tv], room=room)
    assert p.place(sofa, (3.0, 0.2)) is None  # nearest wall: the long bottom one
    assert "tv" in p.layout.placed
    assert abs(item(p, "sofa").front[0]) == pytest.approx(1.0)  # on a short wall instead


def test_parent_not_placed_rug_and_free_items():
    chair = spec("chair", (0.45, 0.5), pair_with="table", can_be_around=True)
    table = spec("table", (1.6, 0.9))
    rug = spec("rug", (2.0, 1.4), non_collision=True)
    p = placer([table, chair, rug])
    assert p.place(chair, None) == "parent table not placed"
    assert p.place(rug, None) is None
    assert item(p, "rug").position == pytest.approx((2.5, 2.0))
    assert item(p, "rug").rotation % 2 == 0  # long side along the room's long side
    assert p.place(table, (0.5, 0.5)) is None  # free-standing: the middle of the room first
    assert item(p, "table").position == pytest.approx((2.5, 2.0))
    assert p.place(chair, None) is None
    big = spec("stage", (4.8, 3.8))
    reason = p.place(big, (2.5, 2.0))
    assert reason.startswith("no free spot for stage (")


def test_side_normals_are_those_made_from_the_front_vector():
    """The table of side normals against the normals made afresh, signed zeros too."""
    for rotation in range(-5, 9):
        f = np.array(front_vector(rotation))
        s = np.array([-f[1], f[0]])
        got = Placer._sides(Pose(0.0, 0.0, rotation))
        assert [v.tobytes() for v in got] == [v.tobytes() for v in (f, -f, s, -s)]
        assert not any(v.flags.writeable for v in got)


# -- items the room itself keeps out -----------------------------------------------------

def test_never_fits_names_the_items_the_room_blocks_everywhere():
    organ = spec("organ", (6.0, 0.5), is_along_wall=True)  # longer than every wall
    lamp = spec("lamp", (0.4, 0.3), is_in_corner=True)
    swings = [Keepout(f"the swing of door {k}", box(x, z, x + 1.0, z + 1.0))
              for k, (x, z) in enumerate([(0, 0), (4, 0), (4, 3), (0, 3)])]
    sofa = spec("sofa", (2.5, 0.9), is_along_wall=True)
    table = spec("table", (1.0, 1.0))
    p = placer([organ, lamp, sofa, table], keepouts=swings)
    assert p.never_fits(organ) and p.never_fits(lamp)  # every corner in a door's swing
    assert not p.never_fits(sofa)  # fits in the 3 m between the swings on a 5 m wall
    assert p.never_fits(spec("long", (3.5, 0.9), is_along_wall=True))  # does not
    assert not p.never_fits(table)  # free items are never judged
    assert not placer([lamp]).never_fits(lamp)


@settings(max_examples=80, deadline=None)
@given(width=st.floats(1.5, 5.0), depth=st.floats(1.5, 5.0),
       size=st.tuples(st.floats(0.3, 4.5), st.floats(0.3, 1.2)),
       corner=st.booleans(), needs_turn=st.booleans(), clearance=st.floats(0.0, 0.8),
       doors=st.lists(st.tuples(st.floats(0.0, 1.0), st.floats(0.6, 2.0)), max_size=6))
def test_never_fits_is_exactly_the_empty_room_refusing_the_item(width, depth, size, corner,
                                                                  needs_turn, clearance, doors):
    """Without other items or a passage rule, the strategy itself is the checker: it
    places the item in the empty room exactly when the room does not block it
    everywhere; and a room that blocks it empty blocks it beside any other item."""
    room = box(0, 0, width, depth)
    rule = {"is_in_corner": True} if corner else {"is_along_wall": True,
                                                  "needs_turn": needs_turn}
    thing = spec("thing", size, clearance_front=clearance, **rule)
    ring = room.exterior
    keepouts = [Keepout(f"the way through door {k}",
                        ring.interpolate(at, normalized=True).buffer(wide / 2, cap_style=3)
                        .intersection(room))
                for k, (at, wide) in enumerate(doors)]
    probe = placer([thing], room=room, keepouts=keepouts)
    never = probe.never_fits(thing)
    empty = placer([thing], room=room, keepouts=keepouts)
    assert (empty.place(thing, (width / 3, depth / 3)) is not None) == never
    if never:
        crowded = placer([thing], room=room, keepouts=keepouts)
        crowded.layout.add(spec("post", (0.2, 0.2)), Pose(width / 2, depth / 2, 0))
        assert crowded.place(thing, (width / 3, depth / 3)) is not None
