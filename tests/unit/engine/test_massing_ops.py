"""extrude, split, repeated_split, component_split on masses and faces."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Point, Polygon, box

from cga.errors import DerivationError
from cga.operation import OperationContext
from cga.operations.component_split import ComponentSplit
from cga.operations.extrude import Extrude
from cga.operations.repeated_split import RepeatedSplit, slice_count
from cga.operations.split import Split, layout
from cga.shape import Face, Mass, Shape

L_SHAPE = Polygon([(0, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)])


def ctx(successors=1, units=1.0):
    return OperationContext(rng=np.random.default_rng(0), units=units, resolve=None,
                            report=lambda d: None, span=None, successor_count=successors)


def mass_shape(footprint=box(0, 0, 10, 6), base=0.0, height=9.0):
    mass = Mass(footprint=footprint, base=base, height=height)
    return Shape(symbol="M", path=("M",), scope=mass.scope(), geometry=mass)


def face_shape(child):
    return Shape(symbol="F", path=("F",), scope=child.scope, geometry=child.geometry)


def newell(vertices):
    pts = np.asarray(vertices, dtype=float)
    n = np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0)
    return n / np.linalg.norm(n)


# -- extrude -------------------------------------------------------------------------------

def test_extrude_lot_to_prism():
    [child] = Extrude().apply(mass_shape(height=0), {"height": 7.5}, ctx())
    assert child.geometry.height == 7.5 and child.geometry.base == 0
    assert child.scope.size == (10, 7.5, 6)


def test_extrude_rejects_non_positive_height():
    with pytest.raises(DerivationError, match="positive, got -2"):
        Extrude().apply(mass_shape(), {"height": -20.0}, ctx(units=10))


def test_extrude_top_face_up_and_bottom_face_down():
    body = mass_shape(height=6)
    [top] = ComponentSplit().apply(body, {"selector": "top"}, ctx())
    [up] = Extrude().apply(face_shape(top), {"height": 2.0}, ctx())
    assert (up.geometry.base, up.geometry.height) == (6, 2)
    assert up.geometry.footprint.equals(body.geometry.footprint)
    [bottom] = ComponentSplit().apply(body, {"selector": "bottom"}, ctx())
    [down] = Extrude().apply(face_shape(bottom), {"height": 1.0}, ctx())
    assert (down.geometry.base, down.geometry.height) == (-1, 1)


def test_extrude_side_face_refused():
    side = ComponentSplit().apply(mass_shape(), {"selector": "side_faces"}, ctx())[0]
    with pytest.raises(DerivationError, match="not horizontal"):
        Extrude().apply(face_shape(side), {"height": 1.0}, ctx())


# -- split layout -------------------------------------------------------------------------------

def test_layout_absolute_floating_relative():
    parts = [("absolute", 2.0, 0), ("floating", 1.0, 1), ("relative", 0.25, 2), ("floating", 3.0, 3)]
    # 12 m: absolute 2, relative 3, floating share 7 as 1:3
    out = layout(12.0, parts, False)
    assert [s for _, _, s in out] == [0, 1, 2, 3]
    assert [v for s, e, _ in out for v in (s, e)] == pytest.approx(
        [0, 2, 2, 3.75, 3.75, 6.75, 6.75, 12])


def test_layout_without_floating_leaves_rest_empty_and_cuts_overflow():
    assert layout(10.0, [("absolute", 3.0, 0), ("absolute", 4.0, 1)], False) == [
        (0, 3, 0), (3, 7, 1)]
    assert layout(10.0, [("absolute", 6.0, 0), ("absolute", 6.0, 1), ("absolute", 1.0, 2)],
                  False) == [(0, 6, 0), (6, 10, 1)]


def test_layout_repeat_with_floating_fills_exactly():
    out = layout(10.0, [("floating", 3.0, 0)], True)
    assert len(out) == 3 and out[-1][1] == 10.0
    assert all(abs((e - s) - 10 / 3) < 1e-12 for s, e, _ in out)
    out = layout(20.0, [("floating", 1.0, 0), ("absolute", 4.0, 1)], True)
    assert [round(e - s, 9) for s, e, _ in out] == [1, 4] * 4


def test_layout_repeat_without_floating_whole_patterns():
    out = layout(10.0, [("absolute", 3.0, 0)], True)
    assert out == [(0, 3, 0), (3, 6, 0), (6, 9, 0)]
    assert layout(2.0, [("absolute", 3.0, 0)], True) == [(0, 2.0, 0)]


def test_layout_repeat_never_overflows_fixed_parts():
    # pattern 4 + ~1 on 9 m: round(9/5) = 2 fits (8 m fixed); on 7 m only 1 fits
    assert len(layout(9.0, [("absolute", 4.0, 0), ("floating", 1.0, 1)], True)) == 4
    assert [round(e - s, 9) for s, e, _ in layout(7.0, [("absolute", 4.0, 0),
                                                        ("floating", 1.0, 1)], True)] == [4, 3]


def test_layout_zero_size_pattern_refused():
    with pytest.raises(DerivationError, match="greater than 0"):
        layout(5.0, [("floating", 0.0, 0)], True)


# -- split geometry ---------------------------------------------------------------------------------

def split(shape, axis, parts, repeat=False, successors=None):
    count = successors or max(p[2] for p in parts) + 1
    return Split().apply(shape, {"axis": axis, "parts": parts, "repeat": repeat}, ctx(count))


def test_split_y_cuts_height():
    children = split(mass_shape(base=1.0), "y", [("absolute", 3.0, 0), ("floating", 1.0, 1)])
    assert [(c.geometry.base, c.geometry.height, c.successor) for c in children] == [
        (1.0, 3.0, 0), (4.0, 6.0, 1)]
    assert [c.attrs["index"] for c in children] == [0, 1]


def test_split_x_of_l_shape_tiles_footprint():
    shape = mass_shape(L_SHAPE)
    children = split(shape, "x", [("floating", 1.0, 0)], repeat=True)
    assert len(children) == 14
    assert sum(c.geometry.footprint.area for c in children) == pytest.approx(L_SHAPE.area)
    assert all(c.scope.size[0] == pytest.approx(1.0) for c in children)


def test_split_z_of_l_shape_falls_apart_into_pieces():
    # Cutting z in [2, 8]: the piece [2, 6] spans the whole width, [6, 8] only x in [0, 8]
    shape = mass_shape(L_SHAPE)
    children = split(shape, "z", [("absolute", 6.0, 0), ("floating", 1.0, 1)])
    assert [c.successor for c in children] == [0, 1]
    assert children[0].geometry.footprint.area == pytest.approx(84)
    assert children[1].geometry.footprint.area == pytest.approx(32)
    u_shape = Polygon([(0, 0), (9, 0), (9, 6), (6, 6), (6, 3), (3, 3), (3, 6), (0, 6)])
    top = split(mass_shape(u_shape), "z", [("absolute", 3.0, 0), ("floating", 1.0, 1)])
    assert [c.successor for c in top] == [0, 1, 1]
    assert [c.attrs["index"] for c in top] == [0, 1, 1]
    assert sorted(c.geometry.footprint.area for c in top[1:]) == pytest.approx([9, 9])


def test_split_flat_shape_refused():
    with pytest.raises(DerivationError, match="no extent along 'y'"):
        split(mass_shape(height=0), "y", [("floating", 1.0, 0)])


def test_split_face_along_x_and_y():
    footprint = Polygon([(0, 0), (10, 0), (10, 6), (0, 6)])
    side = ComponentSplit().apply(mass_shape(footprint, height=6), {"selector": "side_faces"},
                                  ctx())[0]
    assert side.scope.size[0] == 10
    facade = face_shape(side)
    floors = split(facade, "y", [("floating", 3.0, 0)], repeat=True)
    assert len(floors) == 2
    assert [c.scope.size[1] for c in floors] == pytest.approx([3, 3])
    tiles = split(face_shape(floors[1]), "x", [("absolute", 4.0, 0), ("floating", 1.0, 1)])
    assert [c.scope.size[0] for c in tiles] == pytest.approx([4, 6])
    for tile in tiles:
        assert np.allclose(newell(tile.geometry.vertices), newell(side.geometry.vertices))
        ys = [v[1] for v in tile.geometry.vertices]
        assert min(ys) == pytest.approx(3) and max(ys) == pytest.approx(6)
    with pytest.raises(DerivationError, match="a face is flat"):
        split(facade, "z", [("floating", 1.0, 0)])


# -- repeated_split --------------------------------------------------------------------------------

@pytest.mark.parametrize("total,size,n", [(9, 3, 3), (10, 3, 3), (10.5, 3, 4), (2, 3, 1), (1, 3, 1)])
def test_slice_count(total, size, n):
    assert slice_count(total, size) == n


def test_repeated_split_floors_first_and_rest():
    children = RepeatedSplit().apply(mass_shape(height=10), {"axis": "y", "size": 3.0}, ctx(2))
    assert [c.successor for c in children] == [0, 1, 1]
    assert [c.attrs for c in children] == [{"index": i, "floor": i, "floors": 3} for i in range(3)]
    assert [c.geometry.height for c in children] == pytest.approx([10 / 3] * 3)
    assert children[-1].geometry.base + children[-1].geometry.height == 10


def test_repeated_split_single_successor_and_horizontal_axis():
    children = RepeatedSplit().apply(mass_shape(), {"axis": "x", "size": 2.4}, ctx(1))
    assert [c.successor for c in children] == [0] * 4
    assert all("floor" not in c.attrs for c in children)
    assert sum(c.geometry.footprint.area for c in children) == pytest.approx(60)


def test_repeated_split_rejects_non_positive_size():
    with pytest.raises(DerivationError, match="size must be positive"):
        RepeatedSplit().apply(mass_shape(), {"axis": "y", "size": 0.0}, ctx(1))


# -- component_split --------------------------------------------------------------------------------

def test_side_faces_one_per_edge_outward_and_distributed():
    shape = mass_shape(L_SHAPE, base=2.0, height=3.0)
    children = ComponentSplit().apply(shape, {"selector": "side_faces"}, ctx(3))
    assert len(children) == 6
    assert [c.successor for c in children] == [0, 1, 2, 2, 2, 2]
    edges = list(zip(L_SHAPE.exterior.coords[:-1], L_SHAPE.exterior.coords[1:]))
    for child, (a, b) in zip(children, edges):
        face = child.geometry
        assert face.kind == "side"
        normal = newell(face.vertices)
        assert np.allclose(normal, child.scope.axes[2])
        assert normal[1] == pytest.approx(0)
        # outward: the footprint lies on the other side of the edge
        mid = (np.asarray(a) + np.asarray(b)) / 2
        step = 0.01 * np.array([normal[0], normal[2]])
        assert not L_SHAPE.contains(Point(*(mid + step)))
        assert L_SHAPE.contains(Point(*(mid - step)))
        assert child.scope.size[0] == pytest.approx(np.hypot(*np.subtract(b, a)))
        assert child.scope.size[1] == pytest.approx(3.0)
        assert np.allclose(child.scope.axes[1], (0, 1, 0))
        assert [v[1] for v in face.vertices] == pytest.approx([2, 2, 5, 5])


def test_top_and_bottom_faces():
    shape = mass_shape(L_SHAPE, base=1.0, height=4.0)
    [top] = ComponentSplit().apply(shape, {"selector": "top"}, ctx())
    [bottom] = ComponentSplit().apply(shape, {"selector": "bottom"}, ctx())
    assert np.allclose(newell(top.geometry.vertices), (0, 1, 0))
    assert np.allclose(newell(bottom.geometry.vertices), (0, -1, 0))
    assert {v[1] for v in top.geometry.vertices} == {5.0}
    assert {v[1] for v in bottom.geometry.vertices} == {1.0}
    assert top.scope.size == pytest.approx((14, 10, 0))


def test_component_split_errors():
    op = ComponentSplit()
    with pytest.raises(DerivationError) as info:
        op.apply(mass_shape(), {"selector": "side_face"}, ctx())
    assert "did you mean 'side_faces'?" in str(info.value)
    with pytest.raises(DerivationError, match="no height"):
        op.apply(mass_shape(height=0), {"selector": "side_faces"}, ctx())
    with pytest.raises(DerivationError, match="one face; give one successor"):
        op.apply(mass_shape(), {"selector": "top"}, ctx(2))
    side = op.apply(mass_shape(), {"selector": "side_faces"}, ctx())[0]
    with pytest.raises(DerivationError, match="needs a mass"):
        op.apply(face_shape(side), {"selector": "top"}, ctx())
    assert isinstance(side.geometry, Face)


# -- limits ----------------------------------------------------------------------------------

@pytest.mark.parametrize("parts", [
    [("floating", 1e-5, 0)],
    [("absolute", 1e-5, 0)],
    [("relative", 1e-7, 0)],
])
def test_a_repeated_pattern_making_millions_of_pieces_is_refused(parts):
    with pytest.raises(DerivationError, match="would make .* pieces; at most 10,000"):
        layout(24.0, parts, True)


def test_repeated_split_making_millions_of_slices_is_refused():
    with pytest.raises(DerivationError, match="repeated_split size 1e-05 .* at most 10,000"):
        RepeatedSplit().apply(mass_shape(), {"axis": "y", "size": 1e-5}, ctx())


def test_split_sizes_must_be_finite(tmp_path):
    from cga.evaluator import derive
    from cga.parser import parse

    text = "Rules:\nLot --> extrude(10) M\nM --> split(\"y\"){ 1e300 * 1e300 : A }\n"
    with pytest.raises(DerivationError, match="finite number ≥ 0, got inf"):
        derive(parse(text, "g.grammar"), base_dir=tmp_path)
