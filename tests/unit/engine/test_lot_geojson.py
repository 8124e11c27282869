"""Real-world lots (issue 20): GeoJSON footprints in WGS84 or a projected CRS become
plan metres with their georeference; near-rectilinear outlines are squared, holes
filled, and each step is reported.

The failure first seen: a footprint in longitude/latitude (what OpenStreetMap and every
GIS tool give) was read as metres and failed deep in make_floor ("degenerate or not
counter-clockwise"). Areas are checked against pyproj's geodesic area on the WGS84
ellipsoid (``Geod.geometry_area_perimeter``), computed here independently of the
projection the lot reader uses.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from pyproj import CRS, Geod, Transformer
from shapely.geometry import Polygon

from cga.errors import UsageError
from cga.lot import read_lot
from cga.pipeline import build

WGS84 = CRS.from_user_input("OGC:CRS84")
# An L-shaped building (metres): 15 m × 12 m outside, a wing of 8 m × 5 m cut out
L_SHAPE = [(0, 0), (15, 0), (15, 7), (8, 7), (8, 12), (0, 12)]
ORIGIN = (4.8952, 52.3702)  # Amsterdam, lon/lat


def lon_lat(corners, *, turn_deg=0.0, origin=ORIGIN, jitter=None):
    """``corners`` (metres east/north of ``origin``, turned by ``turn_deg``) as WGS84
    longitude/latitude, each moved by ``jitter`` metres (traced-by-hand noise)."""
    local = CRS.from_proj4(f"+proj=aeqd +lat_0={origin[1]} +lon_0={origin[0]} +ellps=WGS84")
    to_degrees = Transformer.from_crs(local, WGS84, always_xy=True)
    a = math.radians(turn_deg)
    points = []
    for k, (x, y) in enumerate(corners):
        dx, dy = jitter[k] if jitter else (0.0, 0.0)
        x, y = x + dx, y + dy
        points.append(to_degrees.transform(x * math.cos(a) - y * math.sin(a),
                                           x * math.sin(a) + y * math.cos(a)))
    return [list(p) for p in points] + [list(points[0])]


def write(tmp_path: Path, geometry: dict, crs: str | None = None, name="lot.geojson") -> Path:
    document: dict = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"building": "yes"}, "geometry": geometry}]}
    if crs is not None:
        document["crs"] = {"type": "name", "properties": {"name": crs}}
    path = tmp_path / name
    path.write_text(json.dumps(document))
    return path


def geodesic_area(ring) -> float:
    area, _ = Geod(ellps="WGS84").geometry_area_perimeter(Polygon(ring))
    return abs(area)


def notes(lot) -> str:
    return " ".join(d.message for d in lot.diagnostics)


def axis_aligned(polygon: Polygon) -> bool:
    coords = np.asarray(polygon.exterior.coords)
    edges = np.diff(coords, axis=0)
    return bool(np.all((np.abs(edges[:, 0]) < 1e-9) | (np.abs(edges[:, 1]) < 1e-9)))


def test_wgs84_building_has_its_ground_area_and_crs(tmp_path):
    ring = lon_lat(L_SHAPE, turn_deg=31.0)
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [ring]})))
    assert lot.polygon.area == pytest.approx(geodesic_area(ring), rel=0.01)
    assert lot.polygon.area == pytest.approx(15 * 7 + 8 * 5, rel=0.001)
    assert lot.georeference.source_crs == "OGC:CRS84"
    assert axis_aligned(lot.polygon)  # turned to its main direction
    assert lot.georeference.rotation_deg == pytest.approx(31.0, abs=0.01)
    assert "WGS84 longitude/latitude" in notes(lot)


def test_plan_corners_map_back_to_the_file(tmp_path):
    """The recorded georeference takes every plan corner back to a corner of the file
    (inverse projection with pyproj, within 2 cm)."""
    ring = lon_lat(L_SHAPE, turn_deg=-12.0)
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [ring]})))
    geo = lot.georeference
    back = Transformer.from_crs(CRS.from_proj4(geo.local_crs), WGS84, always_xy=True)
    geod = Geod(ellps="WGS84")
    for x, z in list(lot.polygon.exterior.coords)[:-1]:
        lon, lat = back.transform(*geo.plan_to_frame(x, z))
        gaps = [geod.inv(lon, lat, p[0], p[1])[2] for p in ring[:-1]]
        assert min(gaps) < 0.02
    lon, lat = geo.origin_lonlat
    assert back.transform(*geo.origin) == pytest.approx((lon, lat), abs=1e-9)


def test_north_is_minus_z(tmp_path):
    """A wing to the north of the main block lies at smaller plan z (the plan pictures
    put north up with z down the page)."""
    ring = lon_lat(L_SHAPE)  # the wing (x 0..8, y 7..12) is the northern part
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [ring]})))
    north_part = lot.polygon.intersection(Polygon([(0, 0), (20, 0), (20, 5), (0, 5)]))
    assert north_part.area == pytest.approx(8 * 5, rel=0.01)  # only the wing is there


def test_a_wgs84_footprint_builds_and_records_its_crs(tmp_path):
    (tmp_path / "one.grammar").write_text(
        "Rules:\nLot --> extrude(3) Storey\n"
        "Storey --> make_floor(4, 0.2, 1>1.2>1.2, 0.9, 2.1) Floor\n"
        'Floor --> type_rooms("house_types.csv") Typed\n')
    ring = lon_lat(L_SHAPE, turn_deg=31.0, jitter=[(0, 0), (0.03, -0.02), (-0.02, 0.04),
                                                    (0.02, 0.01), (0.04, -0.03), (-0.03, 0.02)])
    path = write(tmp_path, {"type": "Polygon", "coordinates": [ring]})
    scene = build(tmp_path / "one.grammar", lot=str(path), physics=False,
                  formats=("json",), out_dir=tmp_path / "out", quiet=True)
    document = json.loads((tmp_path / "out" / "one.scene.json").read_text())
    (floor,) = document["floors"]
    assert floor["area"] == pytest.approx(geodesic_area(ring), rel=0.01)
    georeference = document["georeference"]
    assert georeference["source_crs"] == "OGC:CRS84"
    assert georeference["local_crs"].startswith("+proj=tmerc")
    assert georeference["origin_lonlat"] == pytest.approx(ORIGIN, abs=0.001)
    assert any(d["stage"] == "lot" and "squared the outline" in d["message"]
               for d in document["diagnostics"])
    assert scene.georeference is not None


def test_snapping_is_reported(tmp_path):
    jitter = [(0, 0), (0.05, 0.1), (-0.08, 0.02), (0.04, -0.06), (0.1, 0.05), (-0.05, 0.08)]
    ring = lon_lat(L_SHAPE, turn_deg=8.0, jitter=jitter)
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [ring]})))
    text = notes(lot)
    assert "squared the outline: its 6 walls were at most" in text
    assert "corners moved by at most" in text
    assert axis_aligned(lot.polygon) and len(lot.polygon.exterior.coords) == 7


def test_an_oblique_wall_is_kept_and_reported(tmp_path):
    chamfered = [(0, 0), (12, 0), (12, 6), (8, 10), (0, 10)]
    lot = read_lot(str(write(tmp_path, {"type": "Polygon",
                                        "coordinates": [lon_lat(chamfered)]})))
    assert "not rectilinear" in notes(lot)
    assert any(d.level == "warning" for d in lot.diagnostics)
    assert lot.polygon.area == pytest.approx(12 * 10 - 8, rel=0.001)


def test_the_walls_beside_an_oblique_one_are_squared(tmp_path):
    """A traced outline (corners off by centimetres, turned 8°) with a chamfered corner:
    the chamfer stays oblique, every other wall lies exactly on an axis (where a stair
    core can stand: such a lot failed with "no place for a U stair core"), and the
    warning says both."""
    chamfered = [(0, 0), (16, 0), (16, 8), (13, 11), (0, 11)]
    jitter = [(0, 0), (0.05, 0.1), (-0.08, 0.02), (0.04, -0.06), (0.1, 0.05)]
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [
        lon_lat(chamfered, turn_deg=8.0, jitter=jitter)]})))
    corners = np.asarray(lot.polygon.exterior.coords)
    edges = np.diff(corners, axis=0)
    on_axis = (np.abs(edges) < 1e-9).any(axis=1)
    assert on_axis.sum() == 4 and (~on_axis).sum() == 1
    assert lot.polygon.area == pytest.approx(16 * 11 - 4.5, rel=0.02)
    text = notes(lot)
    assert "not rectilinear: 1 of its 5 walls" in text and "the others squared" in text
    grammar = tmp_path / "two_storeys.grammar"
    grammar.write_text('Rules:\nLot --> extrude(6) Body\nBody --> repeated_split("Y", 3){Storey}\n'
                       'Storey --> make_floor(6, 0.2, 2>1.2>1.3, 0.9, 2.1, min_room_width = 2, '
                       'min_room_area = 4) Floor\n', encoding="utf-8")
    scene = build(grammar, lot=str(tmp_path / "lot.geojson"), formats=(), physics=False,
                  quiet=True)
    assert len(scene.floors[0].stairs) == 1


def test_holes_are_filled_and_reported(tmp_path):
    outer = lon_lat([(0, 0), (20, 0), (20, 20), (0, 20)])
    court = lon_lat([(6, 6), (6, 14), (14, 14), (14, 6)])
    path = write(tmp_path, {"type": "Polygon", "coordinates": [outer, court]})
    lot = read_lot(str(path))
    assert lot.polygon.area == pytest.approx(400, rel=0.001) and not lot.polygon.interiors
    warning = next(d for d in lot.diagnostics if "1 hole" in d.message)
    assert warning.level == "warning" and "1 hole (64.0 m² in all)" in warning.message


def test_a_multipolygon_of_one_part_with_a_hole(tmp_path):
    outer = lon_lat([(0, 0), (20, 0), (20, 20), (0, 20)])
    court = lon_lat([(6, 6), (6, 14), (14, 14), (14, 6)])
    path = write(tmp_path, {"type": "MultiPolygon", "coordinates": [[outer, court]]})
    assert "1 hole" in notes(read_lot(str(path)))


@pytest.mark.parametrize("crs, code", [("urn:ogc:def:crs:EPSG::25831", "EPSG:25831"),
                                       ("EPSG:3857", "EPSG:3857")])
def test_projected_crs_gives_ground_metres(tmp_path, crs, code):
    """UTM and web Mercator coordinates give the ground area (web Mercator's own
    numbers are 1/cos² latitude ≈ 2.7 times too large at 52° N)."""
    ring = lon_lat(L_SHAPE, turn_deg=20.0)
    to_crs = Transformer.from_crs(WGS84, CRS.from_user_input(crs), always_xy=True)
    projected = [list(to_crs.transform(*p)) for p in ring]
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [projected]}, crs)))
    assert lot.polygon.area == pytest.approx(geodesic_area(ring), rel=0.01)
    assert lot.georeference.source_crs == code


def test_local_metres_without_crs(tmp_path):
    ring = [list(p) for p in L_SHAPE + [L_SHAPE[0]]]
    lot = read_lot(str(write(tmp_path, {"type": "Polygon", "coordinates": [ring]})))
    assert lot.polygon.area == pytest.approx(145)
    assert lot.georeference.source_crs is None and lot.georeference.local_crs is None
    assert "local metres" in notes(lot)


@pytest.mark.parametrize("crs, message", [
    ("EPSG:999999", "unknown crs 'EPSG:999999'"),
    ("EPSG:4326", "longitude/latitude, but the coordinates reach"),
])
def test_crs_errors_are_clear(tmp_path, crs, message):
    ring = [[500000, 5800000], [500015, 5800000], [500015, 5800010], [500000, 5800010],
            [500000, 5800000]]
    path = write(tmp_path, {"type": "Polygon", "coordinates": [ring]}, crs)
    with pytest.raises(UsageError, match=message):
        read_lot(str(path))


def test_a_malformed_crs_member_is_refused(tmp_path):
    path = tmp_path / "lot.geojson"
    path.write_text(json.dumps({"type": "Polygon", "crs": "EPSG:4326",
                                "coordinates": [lon_lat(L_SHAPE)]}))
    with pytest.raises(UsageError, match="the crs member must be"):
        read_lot(str(path))


@pytest.mark.parametrize("coordinates", [[], [[]], [[[4.9, 52.3], [4.9, 52.3], [4.9, 52.3],
                                                        [4.9, 52.3]]]])
def test_empty_or_degenerate_polygons_are_refused(tmp_path, coordinates):
    path = tmp_path / "lot.geojson"
    path.write_text(json.dumps({"type": "Polygon", "coordinates": coordinates}))
    with pytest.raises(UsageError, match="lot.geojson"):
        read_lot(str(path))


def test_two_buildings_are_refused(tmp_path):
    a, b = lon_lat(L_SHAPE), lon_lat(L_SHAPE, origin=(4.90, 52.37))
    path = write(tmp_path, {"type": "MultiPolygon", "coordinates": [[a], [b]]})
    with pytest.raises(UsageError, match="exactly one polygon, found 2; a lot is one building"):
        read_lot(str(path))


def test_the_shipped_example_footprint():
    path = Path(__file__).resolve().parents[3] / "demos" / "footprint.geojson"
    ring = json.loads(path.read_text())["features"][0]["geometry"]["coordinates"][0]
    lot = read_lot(str(path))
    assert lot.polygon.area == pytest.approx(geodesic_area(ring), rel=0.01)
    assert axis_aligned(lot.polygon) and len(lot.polygon.exterior.coords) == 7
