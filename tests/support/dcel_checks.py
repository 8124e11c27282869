"""Independent checks of a floor's half-edge structure and plan, used by the tests.

Nothing here calls the DCEL's own methods: the checks read only the raw attributes
(``vertices``, ``half_edges``, ``faces``, ``outside``; ``origin``, ``twin``, ``next``,
``prev``, ``face``, ``edge``; ``x``, ``z``) and use shapely for the geometry, so a bug in
the structure cannot hide behind the same bug in its checker.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import shapely
from scipy import ndimage
from shapely.geometry import LineString, Point, Polygon

__all__ = ["validate_dcel", "validate_plan", "narrowest_room_violation"]

TOL = 1e-6


def _ring_area(points):
    pts = np.asarray(points, dtype=float)
    x, z = pts[:, 0], pts[:, 1]
    return float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)) / 2


def _walk(h, limit):
    cycle = [h]
    e = h.next
    while e is not h:
        cycle.append(e)
        e = e.next
        assert len(cycle) <= limit, f"next cycle from half-edge {h.id} does not close"
    return cycle


def validate_dcel(dcel, footprint: Polygon | None = None) -> None:
    """Assert the half-edge invariants and that the bounded faces tile ``footprint``.

    Checks: twin(twin(e)) = e and twins reversed; next/prev inverse; next starts where
    e ends; one face per cycle, each face's cycle is exactly its half-edges; rooms
    counter-clockwise, the outside clockwise; no edge with one face on both sides; no
    vertex inside another edge (T-junctions are vertices); no duplicate edges; vertex
    ``edge`` starts at the vertex; faces are valid polygons that tile the footprint.
    """
    hs = dcel.half_edges
    n = len(hs)
    assert n % 2 == 0, "odd number of half-edges"
    for e in hs:
        assert e.twin is not e, f"half-edge {e.id} is its own twin"
        assert e.twin.twin is e, f"twin(twin({e.id})) != {e.id}"
        assert e.twin.edge == e.edge, f"half-edge {e.id} and its twin have different edge numbers"
        assert e.next.prev is e, f"prev(next({e.id})) != {e.id}"
        assert e.prev.next is e, f"next(prev({e.id})) != {e.id}"
        assert e.next.origin is e.twin.origin, f"next of {e.id} does not start where {e.id} ends"
        assert e.next.face is e.face, f"next of {e.id} lies on another face"
        assert math.dist((e.origin.x, e.origin.z), (e.twin.origin.x, e.twin.origin.z)) > TOL, \
            f"half-edge {e.id} has zero length"
        assert e.face is not e.twin.face, f"edge {e.edge} has face {e.face.id} on both sides"
    edge_numbers = Counter(e.edge for e in hs)
    assert all(c == 2 for c in edge_numbers.values()), "an edge number is not used by exactly two halves"
    pairs = Counter(frozenset((e.origin.id, e.twin.origin.id)) for e in hs)
    assert all(c == 2 for c in pairs.values()), "two edges join the same pair of vertices"
    for v in dcel.vertices:
        assert v.edge is not None and v.edge.origin is v, f"vertex {v.id}'s edge does not start there"

    faces = list(dcel.faces) + [dcel.outside]
    assert [f.id for f in dcel.faces] == list(range(len(dcel.faces))), "room ids are not 0..n-1"
    covered = set()
    for f in faces:
        cycle = _walk(f.edge, n)
        assert all(e.face is f for e in cycle), f"face {f.id}'s cycle contains foreign half-edges"
        ids = {e.id for e in cycle}
        assert not ids & covered, f"face {f.id} shares a cycle with another face"
        covered |= ids
        area = _ring_area([(e.origin.x, e.origin.z) for e in cycle])
        if f is dcel.outside:
            assert area < -TOL, "the outside cycle is not clockwise"
        else:
            assert area > TOL, f"face {f.id} is not counter-clockwise"
    assert len(covered) == n, "some half-edges belong to no face cycle"

    # No vertex lies inside an edge it is not an end of (missing T-junction).
    pts = np.array([(v.x, v.z) for v in dcel.vertices])
    for e in hs[::1]:
        if e.id > e.twin.id:
            continue
        a = np.array([e.origin.x, e.origin.z])
        b = np.array([e.twin.origin.x, e.twin.origin.z])
        d = b - a
        length = np.linalg.norm(d)
        rel = pts - a
        t = rel @ d / length
        dist = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / length
        inside = (dist < TOL) & (t > TOL) & (t < length - TOL)
        assert not inside.any(), f"a vertex lies inside edge {e.edge} without splitting it"

    polygons = [Polygon([(e.origin.x, e.origin.z) for e in _walk(f.edge, n)]) for f in dcel.faces]
    for f, p in zip(dcel.faces, polygons):
        assert p.is_valid, f"face {f.id} is not a simple polygon"
    union = shapely.union_all(polygons)
    total = sum(p.area for p in polygons)
    assert abs(total - union.area) < 1e-6 * max(1.0, total), "faces overlap"
    outer = Polygon([(e.origin.x, e.origin.z) for e in reversed(_walk(dcel.outside.edge, n))])
    assert union.symmetric_difference(outer).area < 1e-6 * max(1.0, total), \
        "faces do not fill the outside face's boundary"
    if footprint is not None:
        assert union.symmetric_difference(footprint).area < 1e-6 * max(1.0, footprint.area), \
            "faces do not tile the footprint"


def validate_plan(plan) -> None:
    """Assert that the plan agrees with its DCEL and that windows are well placed.

    Every edge is one wall; ``outer`` iff the edge borders the outside; the wall's left
    room lies to the left of start→end; interior walls are shared by exactly two rooms;
    windows lie on outer walls, inside the span, without overlapping, below the top.
    """
    dcel = plan.dcel
    validate_dcel(dcel, plan.footprint)
    by_id = {w.id: w for w in plan.walls}
    assert len(by_id) == len(plan.walls), "duplicate wall ids"
    assert len(plan.walls) == len(dcel.half_edges) // 2, "walls and edges differ in number"
    rooms = {r.id: r for r in plan.rooms}
    assert set(rooms) == {f.id for f in dcel.faces}, "rooms and faces differ"
    t = plan.settings.wall_thickness
    for w in plan.walls:
        left, right = w.rooms
        assert left != right and left >= 0, f"wall {w.id} has rooms {w.rooms}"
        assert w.outer == (right < 0), f"wall {w.id}: outer flag disagrees with its rooms"
        if not w.outer:
            assert left < right, f"inner wall {w.id} should have its lower-id room on the left"
        d = np.subtract(w.end, w.start) / w.length
        mid = np.add(w.start, w.end) / 2
        normal = np.array([-d[1], d[0]])
        probe_left = Point(*(mid + normal * 1e-3))
        probe_right = Point(*(mid - normal * 1e-3))
        assert rooms[left].polygon.contains(probe_left), f"wall {w.id}: room {left} is not on its left"
        if w.outer:
            assert not plan.footprint.contains(probe_right), f"outer wall {w.id} has floor on its right"
        else:
            assert rooms[right].polygon.contains(probe_right), \
                f"wall {w.id}: room {right} is not on its right"
        shared = LineString([w.start, w.end])
        assert rooms[left].polygon.boundary.covers(shared), f"wall {w.id} is not on room {left}'s boundary"
        windows = sorted((o for o in w.openings if o.kind == "window"), key=lambda o: o.center)
        if windows:
            assert w.outer, f"inner wall {w.id} has a window"
        spans = [(o.center - o.width / 2, o.center + o.width / 2) for o in windows]
        for lo, hi in spans:
            assert lo >= t + 0.3 - 1e-6 and hi <= w.length - t - 0.3 + 1e-6, \
                f"window on wall {w.id} is closer than 0.3 m to a corner"
        for (_, hi), (lo, _) in zip(spans, spans[1:]):
            assert lo - hi >= 0.3 - 1e-6, f"windows on wall {w.id} are closer than 0.3 m"
    assert len(plan.windows) == sum(1 for w in plan.walls for o in w.openings if o.kind == "window")
    for win in plan.windows:
        wall = by_id[win.wall]
        assert wall.outer and wall.rooms[0] == win.room
        assert wall.segment().distance(Point(win.position)) < 1e-6
        assert win.sill + win.height <= plan.height - plan.settings.slab_thickness + 1e-9


def narrowest_room_violation(polygon: Polygon, width: float, cell: float = 0.02) -> float:
    """Area (m²) of the room not covered by any ``width`` × ``width`` square inside it.

    Rasterises the room (cell centres) and applies a morphological opening with a
    square one cell narrower than ``width`` (slack for the raster); a room at
    least ``width`` wide everywhere gives 0.
    """
    minx, minz, maxx, maxz = polygon.bounds
    xs = np.arange(minx + cell / 2, maxx, cell)
    zs = np.arange(minz + cell / 2, maxz, cell)
    gx, gz = np.meshgrid(xs, zs)
    polygon = Polygon(polygon.exterior.coords)
    shapely.prepare(polygon)
    inside = shapely.contains_xy(polygon, gx, gz)
    size = max(1, int(math.floor(width / cell + 1e-6)) - 1)
    opened = ndimage.grey_opening(inside.astype(np.uint8), size=(size, size), mode="constant", cval=0)
    return float((inside & (opened == 0)).sum() * cell * cell)
