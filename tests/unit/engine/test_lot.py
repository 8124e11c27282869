"""Lots: --lot forms, GeoJSON, the grammar's Lot: call; validation and orientation."""

import json

import pytest
from shapely.geometry import Polygon

from cga.errors import DerivationError, ResourceNotFoundError, Span, UsageError
from cga.lot import lot_from_call, parse_lot, rectangle

L_SHAPE = [(0, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)]


def is_ccw(polygon: Polygon) -> bool:
    xs, zs = zip(*polygon.exterior.coords)
    return sum(x0 * z1 - x1 * z0 for x0, z0, x1, z1 in zip(xs, zs, xs[1:], zs[1:])) > 0


@pytest.mark.parametrize("text", ["14x10", "14 X 10", "14×10", "rectangle(14, 10)"])
def test_rectangle_forms(text):
    lot = parse_lot(text)
    assert lot.bounds == (0, 0, 14, 10) and lot.area == 140 and is_ccw(lot)


def test_decimal_size():
    assert parse_lot("12.5x8").area == pytest.approx(100)


def test_polygon_form_is_oriented_counter_clockwise():
    clockwise = ",".join(f"({x},{z})" for x, z in reversed(L_SHAPE))
    lot = parse_lot(f"polygon({clockwise})")
    assert lot.area == pytest.approx(14 * 6 + 8 * 4)
    assert is_ccw(lot)


@pytest.mark.parametrize("text", ["14", "14x", "square(3)", "polygon(0,0,1,1)", "x10", ""])
def test_bad_forms_say_what_is_expected(text):
    with pytest.raises(UsageError) as info:
        parse_lot(text)
    message = str(info.value)
    assert ("expected one of" in message) or ("e.g." in message)


def test_self_intersecting_polygon_is_refused():
    with pytest.raises(UsageError, match="not simple"):
        parse_lot("polygon((0,0),(4,4),(4,0),(0,4))")


def test_degenerate_polygons_are_refused():
    with pytest.raises(UsageError, match="at least 3"):
        parse_lot("polygon((0,0),(4,4))")
    with pytest.raises(UsageError):
        parse_lot("polygon((0,0),(1,1),(2,2))")
    with pytest.raises(UsageError, match="positive width"):
        rectangle(0, 3)


@pytest.mark.parametrize("wrap", ["polygon", "feature", "collection"])
def test_geojson_forms(tmp_path, wrap):
    geometry = {"type": "Polygon", "coordinates": [[list(p) for p in L_SHAPE + [L_SHAPE[0]]]]}
    document = {"polygon": geometry,
                "feature": {"type": "Feature", "properties": {}, "geometry": geometry},
                "collection": {"type": "FeatureCollection",
                               "features": [{"type": "Feature", "geometry": geometry}]}}[wrap]
    path = tmp_path / "footprint.geojson"
    path.write_text(json.dumps(document))
    lot = parse_lot(str(path))
    assert lot.area == pytest.approx(116) and is_ccw(lot)
    assert parse_lot("footprint.geojson", base_dir=tmp_path).equals(lot)


def test_geojson_with_two_polygons_or_none(tmp_path):
    square = {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]}
    two = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": square}, {"type": "Feature", "geometry": square}]}
    (tmp_path / "two.geojson").write_text(json.dumps(two))
    with pytest.raises(UsageError, match="exactly one polygon, found 2"):
        parse_lot(str(tmp_path / "two.geojson"))
    (tmp_path / "point.geojson").write_text(json.dumps({"type": "Point", "coordinates": [0, 0]}))
    with pytest.raises(UsageError, match="found 0"):
        parse_lot(str(tmp_path / "point.geojson"))
    (tmp_path / "bad.json").write_text("{nope")
    with pytest.raises(UsageError, match="not a JSON file"):
        parse_lot(str(tmp_path / "bad.json"))


def test_missing_geojson_file(tmp_path):
    with pytest.raises(ResourceNotFoundError, match="lot file not found"):
        parse_lot(str(tmp_path / "nope.geojson"))


def test_grammar_lot_call_scaled_by_units():
    span = Span("g.grammar", 2, 6)
    lot = lot_from_call("polygon", [(0.0, 0.0), (1.4, 0.0), (1.4, 1.0), (0.0, 1.0)], span, 10)
    assert lot.bounds == pytest.approx((0, 0, 14, 10))
    assert lot_from_call("rectangle", [1.4, 1.0], span, 10).area == pytest.approx(140)


def test_grammar_lot_call_errors_carry_the_span():
    span = Span("g.grammar", 2, 6)
    for name, args, text in [("circle", [3.0], "unknown shape 'circle'"),
                             ("rectangle", [1.0], "rectangle takes 2 numbers"),
                             ("polygon", [1.0, 2.0], "polygon takes (x, z) corner pairs"),
                             ("polygon", [(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)],
                              "not simple")]:
        with pytest.raises(DerivationError) as info:
            lot_from_call(name, args, span, 1.0)
        assert str(info.value).startswith("g.grammar:2:6: error: Lot")
        assert text in str(info.value)


@pytest.mark.parametrize("text, message", [
    ("1e308x1e308", "within 100,000 m of the origin"),
    ("polygon((0,0),(1e6,0),(1e6,1),(0,1))", r"a corner coordinate is 1e\+06 m"),
])
def test_absurdly_large_lots_are_refused(text, message):
    with pytest.raises(UsageError, match=message):
        parse_lot(text)


def test_non_finite_corners_are_refused():
    with pytest.raises(UsageError, match="finite coordinates"):
        rectangle(float("inf"), 5)
