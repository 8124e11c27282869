"""Corridor geometry: spine, hall, centre line through L/U/T wings, rooms per side."""

from __future__ import annotations

import pytest
from shapely.geometry import Polygon, box

from cga.operations.floorplan.circulation import (CirculationError, CorridorSpec,
                                                  circulation_faces)



def rect(w, d):
    return [(0, 0), (w, 0), (w, d), (0, d)]


def corridor(footprint, **spec):
    faces = circulation_faces(footprint, CorridorSpec(**spec))
    assert faces[0].circulation
    return Polygon(faces[0].polygon), faces


def test_spine_runs_along_the_long_axis_wall_to_wall():
    poly, faces = corridor(rect(20, 12), mode="spine")
    assert poly.equals(box(0, 5.4, 20, 6.6)) and len(faces) == 1


def test_hall_runs_across_the_short_axis_and_position_moves_it():
    poly, _ = corridor(rect(14, 10), mode="hall", width=1.5, position=0.3)
    assert poly.equals(box(14 * 0.3 - 0.75, 0, 14 * 0.3 + 0.75, 10))


def test_position_keeps_min_depth_on_both_sides():
    poly, _ = corridor(rect(20, 12), mode="spine", position=0.0, min_depth=3)
    assert poly.equals(box(0, 3, 20, 4.2))


def test_too_shallow_for_corridor_and_rooms():
    with pytest.raises(CirculationError, match="6.20 m"):
        circulation_faces(rect(20, 6), CorridorSpec("spine"))


@pytest.mark.parametrize("position, expected", [(0.3, box(0, 0, 20, 1.2)),
                                                 (0.5, box(0, 3.8, 20, 5))])
def test_single_loaded_corridor_runs_along_the_wall_position_leans_to(position, expected):
    poly, faces = corridor(rect(20, 5), mode="spine", position=position, single_loaded=True,
                           n_left=2, n_right=2)
    assert poly.equals(expected)
    rooms = [Polygon(f.polygon) for f in faces[1:]]
    assert len(rooms) == 2 and all(not r.intersection(poly).area for r in rooms)
    with pytest.raises(CirculationError, match="on one side needs 3.70 m"):
        circulation_faces(rect(20, 3.6), CorridorSpec("spine", single_loaded=True))


def test_a_deep_building_gets_parallel_spines_joined_by_a_cross_corridor():
    # 20 m deep: one 1.6 m spine leaves two 9.2 m bands, deeper than 7.5 m
    poly, faces = corridor(rect(30, 20), mode="spine", width=1.6, max_depth=7.5)
    assert len(faces) == 1 and poly.is_valid and not poly.interiors
    spine = [box(0, 5.6, 30, 7.2), box(0, 12.8, 30, 14.4)]
    cross = box(14.2, 7.2, 15.8, 12.8)
    assert poly.symmetric_difference(spine[0].union(spine[1]).union(cross)).area < 1e-9
    free = Polygon(rect(30, 20)).difference(poly)
    bands = sorted(round(g.bounds[3] - g.bounds[1], 6) for g in free.geoms)
    assert bands == [5.6] * 4  # no band deeper than 7.5 m; the middle one halved
    # every band touches a spine along its whole length
    assert all(g.boundary.intersection(poly.boundary).length >= g.bounds[2] - g.bounds[0] - 1e-9
               for g in free.geoms)


@pytest.mark.parametrize("spec", [
    dict(max_depth=7.5),  # 12 m: one spine leaves 5.4 m bands
    dict(max_depth=4, n_left=2, n_right=2),  # rooms counted per side: one spine
])
def test_one_spine_where_bands_are_shallow_enough_or_rooms_are_counted(spec):
    poly, _ = corridor(rect(20, 12), mode="spine", **spec)
    assert poly.equals(box(0, 5.4, 20, 6.6))


def test_rooms_per_side_divide_each_side_evenly():
    _, faces = corridor(rect(20, 12), mode="spine", n_left=4, n_right=2)
    rooms = [Polygon(f.polygon) for f in faces[1:]]
    assert [r.bounds for r in rooms[:4]] == [(5 * k, 0, 5 * k + 5, 5.4) for k in range(4)]
    assert [r.bounds for r in rooms[4:]] == [(0, 6.6, 10, 12), (10, 6.6, 20, 12)]
    assert not any(f.circulation for f in faces[1:])


@pytest.mark.parametrize("footprint, pieces", [
    ([(0, 0), (20, 0), (20, 7), (9, 7), (9, 16), (0, 16)], 2),  # L
    ([(0, 0), (24, 0), (24, 16), (17, 16), (17, 7), (7, 7), (7, 16), (0, 16)], 3),  # U
    ([(0, 0), (24, 0), (24, 7), (15.5, 7), (15.5, 16), (8.5, 16), (8.5, 7), (0, 7)], 2),  # T
])
def test_centre_line_reaches_every_wing_and_leaves_min_depth(footprint, pieces):
    poly, _ = corridor(footprint, mode="centre_line")
    outline = Polygon(footprint)
    assert poly.is_valid and not poly.interiors and outline.covers(poly)
    # one corridor, every wing's far wall reached: it touches the shell in >= pieces places
    touches = poly.boundary.intersection(outline.boundary)
    assert len(getattr(touches, "geoms", [touches])) >= pieces
    # width: eroding by just under half the width leaves a connected spine
    assert poly.buffer(-0.6 + 1e-6, join_style="mitre").geom_type == "Polygon"
    free = outline.difference(poly)
    assert free.buffer(-2.5 / 2 + 1e-6, join_style="mitre").buffer(
        2.5 / 2 - 1e-6, join_style="mitre").area == pytest.approx(free.area, rel=1e-6)


def test_centre_line_refuses_slanted_walls():
    with pytest.raises(CirculationError, match="rectilinear"):
        circulation_faces([(0, 0), (20, 0), (20, 12), (2, 14)], CorridorSpec("centre_line"))


def test_centre_line_on_a_deep_rectangle_is_its_ladder_of_spines():
    ladder, _ = corridor(rect(30, 20), mode="spine", width=1.6, max_depth=7.5)
    centre, _ = corridor(rect(30, 20), mode="centre_line", width=1.6, max_depth=7.5)
    assert centre.equals(ladder)
    shallow, _ = corridor(rect(30, 12), mode="centre_line", width=1.6, max_depth=7.5)
    assert shallow.equals(box(0, 5.2, 30, 6.8))
