"""The plan exporter's shortcuts give the bits of the plain computations they replace.

Each test keeps the plain way (numpy, ``shapely.affinity``, one ``buffer`` per shape,
one point at a time, a cap at both ends of every stroke, a turned label drawn each time)
and compares exactly: coordinates bit for bit, geometries as WKB, pages as PNG bytes.
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings, strategies as st
from PIL import Image
from shapely import affinity
from shapely.geometry import Point, Polygon
from shapely.ops import unary_union

from cga.export import drawing
from cga.export.drawing import Area, Drawing, Polyline, Style, Text, render_png
from cga.export.plan import _HATCHING, _corners, _hatch, _obstacles, _Paper, _scale_x
from cga.model import OUTSIDE, Wall

DEMOS = Path(__file__).resolve().parents[3] / "demos"

coordinate = st.one_of(st.floats(-60.0, 60.0, allow_nan=False), st.sampled_from([0.0, -0.0]))


def _bits(geometry) -> bytes:
    return shapely.get_coordinates(geometry).tobytes()


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(coordinate, coordinate), min_size=3, max_size=12),
       st.floats(0.01, 50.0))
def test_scale_x_gives_the_coordinates_of_affinity_scale(points, factor):
    ring = Polygon(points)
    for geometry in (ring, shapely.multipolygons([ring, affinity.translate(ring, 100.0)])):
        expected = affinity.scale(geometry, xfact=factor, yfact=1.0, origin=(0, 0))
        assert _bits(_scale_x(geometry, factor)) == _bits(expected)


def _numpy_corners(wall, s0, s1, lo, hi):
    start, u, n = np.asarray(wall.start), wall.direction, wall.normal
    return [(float(x), float(z)) for x, z in (start + u * s + n * o for s, o in
                                              ((s0, lo), (s1, lo), (s1, hi), (s0, hi)))]


@settings(max_examples=300, deadline=None)
@given(st.tuples(coordinate, coordinate), st.tuples(coordinate, coordinate),
       st.floats(-5.0, 5.0), st.floats(-5.0, 5.0), st.floats(-0.5, 0.5), st.floats(-0.5, 0.5),
       st.booleans())
def test_wall_corners_in_floats_are_the_numpy_sums(start, end, s0, s1, lo, hi, axis):
    if axis:  # most walls run along an axis
        end = (end[0], start[1])
    if math.dist(start, end) < 1e-3:
        return
    wall = Wall(0, start, end, True, (0, OUTSIDE), 0.2)
    assert _corners(wall, s0, s1, lo, hi) == _numpy_corners(wall, s0, s1, lo, hi)


@pytest.fixture(scope="module")
def house_floors():
    from cga.pipeline import build

    return build(DEMOS / "house.grammar", seed=0, formats=(), physics=False, quiet=True).floors


def test_label_obstacles_are_the_union_of_each_shape_buffered(house_floors):
    for plan in house_floors:
        furniture = [item.footprint() for item in plan.furniture if not item.is_detail]
        swings = [Point(*door.position).buffer(door.width + 0.05) for door in plan.doors]
        stairs = [stair.polygon.buffer(0.05) for stair in plan.stairs]
        expected = unary_union([f.buffer(0.05) for f in furniture] + swings + stairs)
        assert shapely.to_wkb(_obstacles(plan, furniture)) == shapely.to_wkb(expected)


def test_a_closed_stroke_capped_once_paints_the_page_of_two_caps(monkeypatch):
    page = Drawing(width=90, height=70, title="caps")
    ring = ((10.3, 10.7), (70.1, 12.2), (60.6, 55.5), (15.2, 50.9))
    page.add("a", Area((ring,), Style(fill="#f3efe7", stroke="#2f2b27", width=1.0)))
    page.add("a", Polyline(ring, Style(stroke="#a33b2b", width=1.8), closed=True))
    page.add("a", Polyline(ring, Style(stroke="#5d5d5d", width=1.0, dash=(5.0, 3.0)),
                           closed=True))
    page.add("a", Polyline(ring[:3], Style(stroke="#7d7369", width=1.2)))
    once = render_png(page)
    monkeypatch.setattr(drawing, "_ends", lambda piece: (piece[0], piece[-1]))
    assert once == render_png(page)
    assert Image.open(io.BytesIO(once)).size == (90, 70)


def test_turned_labels_drawn_once_paint_the_page_of_labels_drawn_each_time(monkeypatch):
    page = Drawing(width=160, height=90, title="labels")
    for k, (x, y) in enumerate(((20.3, 60.7), (45.5, 61.2), (70.81, 58.06), (95.0, 70.0))):
        page.add("a", Text((x, y), "chair", 8.5, angle=90, anchor=("middle", "start")[k % 2]))
        page.add("a", Text((x + 10.2, y), "bed", 7.5, "#5d544a", angle=90, bold=k == 3))
    drawing._turned_text.cache_clear()
    kept = render_png(page)
    assert drawing._turned_text.cache_info().hits > 0
    monkeypatch.setattr(drawing, "_turned_text", drawing._turned_text.__wrapped__)
    assert kept == render_png(page)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(coordinate, coordinate), max_size=20),
       st.tuples(coordinate, coordinate), st.floats(1.0, 120.0))
def test_paper_points_in_one_pass_are_the_points_one_by_one(points, corner, scale):
    paper = _Paper(corner[0], corner[1], scale, 48.0, 56.0)
    array = np.array(points, dtype=float).reshape(-1, 2)
    expected = [paper.point(x, z) for x, z in points]
    assert np.array(paper.points(array)).tobytes() == np.array(expected).tobytes()


def _hatch_one_part_at_a_time(paper, region):
    """The hatch lines as :func:`_hatch` read them before: part by part, point by point."""
    min_x, min_z, max_x, max_z = region.bounds
    spacing = max(0.35, 6.0 / paper.scale)
    count = int(((max_x - min_x) + (max_z - min_z)) / spacing) + 1
    lines = shapely.linestrings([[(c - min_z + 1, min_z - 1), (c - max_z - 1, max_z + 1)]
                                 for c in (min_x + min_z + k * spacing for k in range(count + 1))])
    return [Polyline(tuple(paper.point(x, z) for x, z in part.coords), _HATCHING,
                     css_class="circulation")
            for piece in shapely.intersection(lines, region)
            for part in getattr(piece, "geoms", [piece])
            if part.geom_type == "LineString" and not part.is_empty]


@pytest.mark.parametrize("region", [
    Polygon([(0.3, 0.2), (4.1, 0.2), (4.1, 1.4), (1.5, 1.4), (1.5, 3.9), (0.3, 3.9)]),  # an L
    Polygon([(0, 0), (3.5, 0), (3.5, 2.8), (0, 2.8)],  # a hall around a stair core
            [[(1.0, 0.7), (2.4, 0.7), (2.4, 2.1), (1.0, 2.1)]]),
    Polygon([(0, 0), (0.7, 0), (0.7, 0.7), (1.4, 0.7), (1.4, 0), (2.1, 0), (2.1, 1.4),
             (0, 1.4)]),  # corners on hatch lines: grazing points, not lines
])
def test_hatch_lines_read_in_one_pass_are_the_lines_read_one_by_one(region):
    paper = _Paper(-0.5, -0.5, 40.0, 48.0, 80.0)
    page = Drawing(width=400, height=300, title="hatch")
    _hatch(page, paper, region)
    assert page.layers["rooms"] == _hatch_one_part_at_a_time(paper, region)
