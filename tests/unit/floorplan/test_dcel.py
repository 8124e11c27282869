"""The half-edge structure: construction, edge and face splits, queries."""

from __future__ import annotations

import pytest
from shapely.geometry import box

from cga.model import OUTSIDE, FloorSettings
from cga.operations.floorplan.assemble import plan_from_dcel
from cga.operations.floorplan.dcel import DCEL
from dcel_checks import validate_dcel, validate_plan

SQUARE = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]


def test_thesis_check_one_split_of_a_2x2_floor():
    """Thesis §6.1, Abb. 6.4: one split gives two rooms of four walls each, eight
    half-edges in rooms, the new pair inner and the rest outer."""
    dcel = DCEL.from_polygon(SQUARE)
    dcel.split_face(dcel.faces[0], (1.0, 0.0), (1.0, 2.0))
    validate_dcel(dcel, box(0, 0, 2, 2))
    assert len(dcel.faces) == 2
    cycles = [dcel.boundary(f) for f in dcel.faces]
    assert [len(c) for c in cycles] == [4, 4]
    in_rooms = [h for c in cycles for h in c]
    assert len(in_rooms) == 8
    inner = [h for h in in_rooms if not h.twin.face.is_outside]
    assert len(inner) == 2 and inner[0].twin is inner[1]
    assert {h.start for h in inner} == {(1.0, 0.0), (1.0, 2.0)}
    plan = plan_from_dcel(dcel, settings=FloorSettings(windows_per_wall=0), index=0,
                          elevation=0.0, height=3.0)
    validate_plan(plan)
    for room in plan.rooms:
        walls = plan.walls_of(room.id)
        assert len(walls) == 4
        assert sorted(w.outer for w in walls) == [False, True, True, True]


def test_from_polygon_builds_room_and_outside():
    dcel = DCEL.from_polygon(SQUARE)
    validate_dcel(dcel)
    assert len(dcel.vertices) == 4 and len(dcel.half_edges) == 8 and dcel.edge_count == 4
    assert dcel.points(dcel.faces[0]) == SQUARE
    assert dcel.area(dcel.faces[0]) == pytest.approx(4.0)
    assert dcel.face(OUTSIDE) is dcel.outside
    assert [h.start for h in dcel.outer_boundary()] == SQUARE


def test_split_edge_inserts_vertex_on_both_sides():
    dcel = DCEL.from_polygon(SQUARE)
    bottom = dcel.faces[0].edge
    assert (bottom.start, bottom.end) == ((0.0, 0.0), (2.0, 0.0))
    v = dcel.split_edge(bottom, (0.5, 0.0))
    validate_dcel(dcel)
    assert v.point == (0.5, 0.0)
    assert bottom.end == (0.5, 0.0) and bottom.next.start == (0.5, 0.0) and bottom.next.end == (2.0, 0.0)
    assert bottom.twin.start == (0.5, 0.0) and bottom.twin.end == (0.0, 0.0)
    assert len(dcel.points(dcel.faces[0])) == 5 and len(dcel.points(dcel.outside)) == 5
    assert dcel.edge_count == 5
    assert sorted(h.end for h in v.outgoing()) == [(0.0, 0.0), (2.0, 0.0)]


@pytest.mark.parametrize("point", [(0.0, 0.0), (2.0, 0.0), (1.0, 0.5), (3.0, 0.0)])
def test_split_edge_rejects_points_off_the_open_edge(point):
    dcel = DCEL.from_polygon(SQUARE)
    with pytest.raises(ValueError):
        dcel.split_edge(dcel.faces[0].edge, point)


def test_split_face_through_existing_vertices():
    dcel = DCEL.from_polygon(SQUARE)
    h = dcel.split_face(dcel.faces[0], (0.0, 0.0), (2.0, 2.0))
    validate_dcel(dcel, box(0, 0, 2, 2))
    assert len(dcel.vertices) == 4
    assert h.face is dcel.faces[0] and h.twin.face is dcel.faces[1]
    assert dcel.area(dcel.faces[0]) == pytest.approx(2.0) and dcel.area(dcel.faces[1]) == pytest.approx(2.0)


def test_t_junction_becomes_a_vertex_shared_by_both_rooms():
    dcel = DCEL.from_polygon([(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)])
    up = dcel.split_face(dcel.faces[0], (2.0, 0.0), (2.0, 2.0))
    # The face keeps the side left of the cut (west of a cut going +z); the east is new.
    assert up.face.id == 0 and up.twin.face.id == 1
    assert min(x for x, _ in dcel.points(dcel.faces[1])) == 2.0
    east = dcel.split_face(dcel.faces[1], (2.0, 1.0), (4.0, 1.0))
    assert east.face.id == 1 and east.twin.face.id == 2  # 1 is north-east, 2 south-east
    validate_dcel(dcel, box(0, 0, 4, 2))
    assert (2.0, 1.0) in dcel.points(dcel.faces[0])  # the T-junction is on the west room too
    assert [(h.start, h.end) for h in dcel.shared_edges(0, 2)] == [((2.0, 0.0), (2.0, 1.0))]
    assert [(h.start, h.end) for h in dcel.shared_edges(0, 1)] == [((2.0, 1.0), (2.0, 2.0))]
    assert dcel.shared_edges(0, 1)[0].twin is dcel.shared_edges(1, 0)[0]
    assert dcel.neighbours(0) == [OUTSIDE, 1, 2]
    assert dcel.adjacency() == {0: [OUTSIDE, 1, 2], 1: [OUTSIDE, 0, 2], 2: [OUTSIDE, 0, 1]}


def test_split_face_of_l_shape_with_reflex_corner():
    l_shape = [(0, 0), (6, 0), (6, 3), (3, 3), (3, 6), (0, 6)]
    dcel = DCEL.from_polygon(l_shape)
    dcel.split_face(dcel.faces[0], (0.0, 3.0), (3.0, 3.0))  # ends on the reflex corner
    validate_dcel(dcel)
    assert sorted(round(dcel.area(f), 6) for f in dcel.faces) == [9.0, 18.0]


@pytest.mark.parametrize("p, q", [
    ((0.0, 0.0), (2.0, 0.0)),        # along the boundary
    ((0.0, 0.0), (1.0, 0.0)),        # half along the boundary
    ((1.0, 0.0), (1.0, 1.0)),        # ends inside the face
    ((1.0, 0.0), (1.0, 0.0)),        # zero length
])
def test_split_face_rejects_non_chords(p, q):
    dcel = DCEL.from_polygon(SQUARE)
    with pytest.raises(ValueError):
        dcel.split_face(dcel.faces[0], p, q)


def test_split_face_rejects_chord_leaving_a_concave_face():
    dcel = DCEL.from_polygon([(0, 0), (6, 0), (6, 3), (3, 3), (3, 6), (0, 6)])
    with pytest.raises(ValueError):
        dcel.split_face(dcel.faces[0], (6.0, 1.5), (1.5, 6.0))
    with pytest.raises(ValueError):
        dcel.split_face(dcel.outside, (0.0, 1.0), (6.0, 1.0))


def test_from_polygons_matches_shared_boundaries():
    dcel = DCEL.from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(1, 0), (2, 0), (2, 1), (1, 1)]])
    validate_dcel(dcel, box(0, 0, 2, 1))
    assert len(dcel.shared_edges(0, 1)) == 1 and dcel.edge_count == 7


@pytest.mark.parametrize("polygons, message", [
    ([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 0), (1, 0), (1, 1), (0, 1)]], "overlap"),
    ([[(0, 0), (0, 1), (1, 1), (1, 0)]], "counter-clockwise"),
    ([[(0, 0), (1, 0), (1, 1), (0, 1)], [(1, 1), (2, 1), (2, 2), (1, 2)]], "touches itself"),
    ([[(0, 0), (1, 0), (1, 1), (0, 1)], [(2, 0), (3, 0), (3, 1), (2, 1)]], "hole or is not connected"),
])
def test_from_polygons_rejects_bad_tilings(polygons, message):
    with pytest.raises(ValueError, match=message):
        DCEL.from_polygons(polygons)
