"""The layout's quick paths give exactly what the general code gives.

Rectangular storeys take shortcuts (DESIGN §11, benchmarks/bench_layout.py): room
interiors without GEOS' overlay, door-swing containment and wall directions without
shapely or numpy, cut positions a rectangular leaf cannot take skipped before the exact
test. Each is checked here against the general computation it stands in for, bit for bit.
"""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.model import Wall
from cga.operations.floorplan.assemble import box_interiors
from cga.operations.floorplan.bsp import _best_chord, _candidates, _rectangle_window, _Rules
from cga.operations.roomtyping.doors import _axis_aligned_box, _leaf_frame_xy

CM = st.integers(0, 3000).map(lambda v: v / 100)


@st.composite
def storeys(draw):
    """A rectangular footprint, one rectangular room in it (its ring starting anywhere,
    with T-junction vertices on some sides) and a wall thickness."""
    width, depth = draw(st.integers(400, 3000)) / 100, draw(st.integers(400, 3000)) / 100
    ox, oz = draw(st.integers(-5000, 5000)) / 100, draw(st.integers(-5000, 5000)) / 100
    x0 = draw(st.one_of(st.just(0.0), st.integers(0, round(width * 100) - 150).map(lambda v: v / 100)))
    z0 = draw(st.one_of(st.just(0.0), st.integers(0, round(depth * 100) - 150).map(lambda v: v / 100)))
    x1 = draw(st.one_of(st.just(width), st.integers(round(x0 * 100) + 100, round(width * 100)).map(lambda v: v / 100)))
    z1 = draw(st.one_of(st.just(depth), st.integers(round(z0 * 100) + 100, round(depth * 100)).map(lambda v: v / 100)))
    x0, x1, z0, z1 = x0 + ox, x1 + ox, z0 + oz, z1 + oz
    ring = [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]
    if draw(st.booleans()):
        ring.insert(1, (round(x0 + draw(st.floats(0.2, 0.8)) * (x1 - x0), 2), z0))
    if draw(st.booleans()):
        ring.append((x0, round(z1 - draw(st.floats(0.2, 0.8)) * (z1 - z0), 2)))
    first = draw(st.integers(0, len(ring) - 1))
    footprint = Polygon([(ox, oz), (ox + width, oz), (ox + width, oz + depth), (ox, oz + depth)])
    thickness = draw(st.sampled_from([0.1, 0.12, 0.15, 0.2, 0.25, 0.3]))
    return footprint, Polygon(ring[first:] + ring[:first]), thickness


@settings(max_examples=200, deadline=None)
@given(storeys())
def test_box_interiors_are_the_overlay(storey):
    footprint, room, t = storey
    shrunk = footprint.buffer(-t, join_style="mitre")
    offsets = shapely.buffer(np.array([room]), -t / 2, join_style="mitre")
    [fast] = box_interiors(offsets, shrunk)
    overlay = shapely.simplify(shapely.intersection(offsets[0], shrunk, grid_size=1e-6), 0.0)
    if fast is None:  # left to the overlay: edges within a few µm, or nothing left
        return
    assert list(fast.exterior.coords) == list(orient(overlay).exterior.coords)


def test_box_interiors_leave_other_shapes_to_the_overlay():
    ell = Polygon([(0, 0), (10, 0), (10, 4), (4, 4), (4, 8), (0, 8)])
    shrunk = Polygon([(0, 0), (20, 0), (20, 20), (0, 20)]).buffer(-0.2, join_style="mitre")
    offsets = shapely.buffer(np.array([ell, Polygon([(1, 1), (5, 1), (5, 5), (1, 5)])]), -0.1,
                             join_style="mitre")
    fast = box_interiors(offsets, shrunk)
    assert fast[0] is None and fast[1] is not None
    assert box_interiors(offsets, ell.buffer(-0.2, join_style="mitre")) == [None, None]


@given(st.tuples(CM, CM), st.tuples(CM, CM), st.floats(-5, 40))
def test_wall_points_match_numpy(start, end, distance):
    wall = Wall(0, start, end, False, (0, 1), 0.2)
    if start == end:
        return
    d = np.subtract(end, start)
    direction = d / np.linalg.norm(d)
    p = np.asarray(start) + direction * distance
    assert wall.point_at(distance) == (float(p[0]), float(p[1]))
    assert wall.direction.tolist() == direction.tolist()


@given(st.tuples(CM, CM, CM, CM))
def test_axis_aligned_box(values):
    x0, z0, x1, z1 = values
    polygon = Polygon([(x0, z0), (x1, z0), (x1, z1), (x0, z1)])
    if x0 == x1 or z0 == z1:
        return
    assert _axis_aligned_box(polygon) == polygon.bounds
    assert _axis_aligned_box(Polygon([(x0, z0), (x1, z0), (x1, z1)])) is None


@settings(max_examples=150, deadline=None)
@given(st.integers(300, 2000), st.integers(300, 2000), st.floats(1.0, 3.0), st.floats(0, 12),
       st.floats(0, 3), st.lists(st.booleans(), min_size=4, max_size=4))
def test_rectangle_window_never_drops_a_valid_cut(w, d, min_width, min_area, min_contact, contact):
    """Every cut position the exact test accepts lies inside the window."""
    ring = [(0.0, 0.0), (w / 100, 0.0), (w / 100, d / 100), (0.0, d / 100)]
    rules = _Rules(min_width, min_area, (0.35, 0.65), 0.01, 0.5, min_contact)
    flags = contact if any(contact) and min_contact > 0 else None
    for k in (0, 1):
        lo, hi = window = _rectangle_window(ring, k, rules, flags)
        marks = sorted({p[k] for p in ring})
        for position in _candidates((marks[0] + marks[1]) / 2, marks, rules):
            if _best_chord(ring, k, position, rules, flags) is not None:
                assert lo <= position <= hi, (position, window)


@given(st.tuples(CM, CM), st.tuples(CM, CM), st.floats(0, 30), st.sampled_from(["start", "end"]),
       st.booleans(), st.booleans())
def test_leaf_frame_matches_the_wall_geometry(start, end, centre, hinge, left, outer):
    """The door leaf's frame in plain floats is the numpy computation of Wall's methods."""
    if start == end:
        return
    wall = Wall(0, start, end, outer, (3, -1 if outer else 4), 0.2)
    room = 3 if left or outer else 4
    d = wall.direction
    normal = wall.normal_into(room)
    jamb = centre - 0.45 if hinge == "start" else centre + 0.45
    pivot = np.asarray(wall.point_at(jamb)) + normal * wall.face_offset(room)
    got = _leaf_frame_xy(wall, centre, 0.9, hinge, room)
    assert got == (tuple(pivot.tolist()), tuple((d if hinge == "start" else -d).tolist()),
                   tuple(normal.tolist()))
