"""The lot: the footprint polygon a derivation starts from.

A lot comes from the command line (``--lot``), from the grammar's ``Lot:`` line, or is
the default rectangle. Every form ends as a valid shapely :class:`~shapely.geometry.Polygon`
in plan coordinates ``(x, z)``, metres, exterior counter-clockwise in those coordinates
(shapely's ``orient(sign=1)``), not self-intersecting, with positive area. The formats
are documented for users in docs/lots.md.

Accepted ``--lot`` forms::

    14x10  14x10m                           a 14 m × 10 m rectangle at the origin (a size
                                            without a unit is metres)
    1.4x1u                                  1.4 × 1 grammar units (× the grammar's units)
    rectangle(14, 10)                       the same in metres; ``rectangle(1.4, 1)u``
                                            in grammar units
    "polygon((0,0),(14,0),(14,6),(8,6),(8,10),(0,10))"   corners, metres (``...)u``:
                                            grammar units)
    footprint.geojson                       a GeoJSON Polygon or MultiPolygon, a Feature
                                            with one, or a FeatureCollection holding
                                            exactly one polygon: WGS84 longitude/latitude,
                                            a projected CRS, or local metres
                                            (:mod:`cga.georeference`); squared when
                                            nearly rectilinear (:mod:`cga.rectify`)

The grammar's ``Lot: rectangle(w, d)`` / ``Lot: polygon(...)`` uses the same shapes in
grammar units; :func:`lot_from_call` scales them by ``units``.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from shapely import affinity
from shapely.geometry import MultiPolygon, Polygon, shape as geojson_shape
from shapely.geometry.polygon import orient
from shapely.validation import explain_validity

from .errors import BudgetError, DerivationError, Span, UsageError, excerpt
from .georeference import (Georeference, SourceFrame, frame_to_lonlat, source_frame,
                           to_local_metres)
from .model import Diagnostic
from .provenance import note_input
from .rectify import SNAP_TOLERANCE_DEG, edge_deviation, main_direction, square
from .textfiles import read_input_bytes

if TYPE_CHECKING:  # pragma: no cover
    from .sandbox import Sandbox

__all__ = ["DEFAULT_LOT", "MAX_EXTENT", "MAX_LOT_VERTICES", "MAX_LOT_FILE_BYTES", "LOT_FORMATS",
           "LotInput", "validate_lot", "rectangle", "polygon_lot", "read_lot", "parse_lot",
           "read_geojson", "load_geojson", "lot_from_call"]

DEFAULT_LOT = (14.0, 10.0)
"""Width (x) and depth (z) in metres of the lot used when neither CLI nor grammar gives one."""

MAX_EXTENT = 100_000.0
"""Largest lot side and longest length argument accepted, in metres (100 km). Far beyond
any building; larger coordinates lose the precision the geometry needs and can stall
GEOS (an infinite area never converges)."""

MAX_LOT_VERTICES = 1_000
"""Most corners a lot may have. A building footprint has tens; every storey's BSP, walls
and rasters grow with the corner count (a 200,000-corner lot ran for minutes)."""

MAX_LOT_FILE_BYTES = 10_000_000
"""Largest GeoJSON lot file read (10 MB)."""

LOT_FORMATS = ('14x10 or 14x10m (width x depth in metres)', '1.4x1u (in grammar units)',
               '"rectangle(14, 10)"', '"polygon((0,0),(14,0),(14,10),(0,10))"',
               "a .geojson file with one polygon (docs/lots.md)")
"""The ``--lot`` forms, as listed in error messages."""

_PLAN_DECIMALS = 3
"""A GeoJSON footprint's plan corners are rounded to this many decimals of a metre."""

_NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
_SIZE = re.compile(rf"^\s*({_NUMBER})\s*[xX×*]\s*({_NUMBER})\s*([mMuU])?\s*$")
_CALL = re.compile(r"^\s*(rectangle|polygon)\s*\((.*)\)\s*([mu])?\s*$",
                   re.IGNORECASE | re.DOTALL)
_POINT = re.compile(rf"\(\s*({_NUMBER})\s*,\s*({_NUMBER})\s*\)")
_RECT_ARGS = re.compile(rf"^\s*({_NUMBER})\s*,\s*({_NUMBER})\s*$")


def _expected() -> str:
    return "expected one of: " + "; ".join(LOT_FORMATS)


def validate_lot(polygon: Polygon, what: str = "lot") -> Polygon:
    """``polygon`` checked (simple, at least 3 corners, finite coordinates within
    :data:`MAX_EXTENT` of the origin, positive area) and oriented
    counter-clockwise in plan coordinates.

    Raises
    ------
    UsageError
        Saying what is wrong, prefixed by ``what``.
    """
    if not isinstance(polygon, Polygon):
        raise UsageError(f"{what}: expected a shapely Polygon, got {type(polygon).__name__}")
    if polygon.is_empty or len(polygon.exterior.coords) < 4:
        raise UsageError(f"{what}: a lot needs at least 3 distinct corners")
    if polygon.has_z:
        raise UsageError(f"{what}: a lot is a plan footprint with (x, z) corners in metres; "
                         f"these corners have a third coordinate")
    if len(polygon.exterior.coords) - 1 + sum(len(r.coords) - 1 for r in polygon.interiors) \
            > MAX_LOT_VERTICES:
        raise BudgetError(f"{what}: the lot has {len(polygon.exterior.coords) - 1:,} corners; "
                          f"at most {MAX_LOT_VERTICES:,} are allowed (docs/limits.md)")
    coords = np.asarray(polygon.exterior.coords)
    if not np.isfinite(coords).all():
        raise UsageError(f"{what}: every corner needs finite coordinates")
    if np.abs(coords).max() > MAX_EXTENT:
        raise UsageError(f"{what}: a corner coordinate is {np.abs(coords).max():.4g} m; a lot "
                         f"must stay within {MAX_EXTENT:,.0f} m of the origin along x and z")
    if not polygon.is_valid:
        raise UsageError(f"{what}: the polygon is not simple ({explain_validity(polygon)}); "
                         f"list the corners in order around the boundary without crossings")
    if polygon.area <= 0:
        raise UsageError(f"{what}: the polygon has zero area")
    return orient(polygon, sign=1.0)


def rectangle(width: float, depth: float) -> Polygon:
    """A ``width`` × ``depth`` rectangle with a corner at the origin (metres).

    Raises
    ------
    UsageError
        A side is not positive.
    """
    if not (width > 0 and depth > 0):
        raise UsageError(f"a rectangular lot needs positive width and depth, got "
                         f"{width:g} m x {depth:g} m")
    return validate_lot(Polygon([(0, 0), (width, 0), (width, depth), (0, depth)]),
                      f"rectangle {width:g} m x {depth:g} m")


def polygon_lot(points: Sequence[Sequence[float]], what: str = "polygon") -> Polygon:
    """A lot from corner points ``(x, z)`` in order (metres), validated and oriented.

    Raises
    ------
    UsageError
        Fewer than 3 corners, self-intersecting, or zero area.
    """
    coords = [(float(p[0]), float(p[1])) for p in points]
    if len(coords) < 3:
        raise UsageError(f"{what}: a lot needs at least 3 corners, got {len(coords)}")
    return validate_lot(Polygon(coords), what)


@dataclass(frozen=True)
class LotInput:
    """A lot as read from ``--lot``: the plan ``polygon`` (metres), the unit its numbers
    were read in (``"m"`` or ``"grammar"``; ``unit_stated`` False when the text gave
    none and metres were assumed), where it lies in the world (``georeference``, for a
    GeoJSON file) and what reading it decided (``diagnostics``: CRS, squaring, holes)."""

    polygon: Polygon
    text: str
    unit: Literal["m", "grammar"] = "m"
    unit_stated: bool = True
    georeference: Georeference | None = None
    diagnostics: tuple[Diagnostic, ...] = ()

    def unit_hint(self, units: float) -> str | None:
        """A hint for a failed build when this lot's size may be in the wrong unit: a
        plain ``WxD`` (metres by default) under a grammar whose units are not metres."""
        if self.unit_stated or units == 1:
            return None
        minx, minz, maxx, maxz = self.polygon.bounds
        width, depth = maxx - minx, maxz - minz
        return (f"--lot {excerpt(self.text)} was read in metres (a {width:g} m × {depth:g} m "
                f"lot, {self.polygon.area:g} m²), but this grammar's lengths are in units of "
                f"{units:g} m; for {width:g} × {depth:g} grammar units "
                f"({width * units:g} m × {depth * units:g} m) write --lot "
                f"{width:g}x{depth:g}u, or --lot {width:g}x{depth:g}m to keep metres")


def load_geojson(path: str | Path, *, sandbox: "Sandbox | None" = None) -> Polygon:
    """The plan polygon of a GeoJSON lot file (see :func:`read_geojson`)."""
    return read_geojson(path, sandbox=sandbox).polygon


def read_geojson(path: str | Path, *, sandbox: "Sandbox | None" = None) -> LotInput:
    """The single polygon of a GeoJSON file (Polygon, MultiPolygon of one part, Feature
    or FeatureCollection), in plan metres, with its georeference.

    The coordinates are read in the file's CRS (:func:`cga.georeference.source_frame`),
    projected to a local transverse Mercator, turned so plan ``x`` follows the outline's
    main direction, squared (every edge within :data:`~cga.rectify.SNAP_TOLERANCE_DEG` of a
    right angle put on its axis, others kept) and moved so the bounding box starts at the
    plan origin. Holes
    (courtyards) are filled. Each of these steps is a diagnostic.

    ``sandbox``, when given, holds the folders the file may lie in (:mod:`cga.sandbox`).

    Raises
    ------
    ResourceNotFoundError
        The file does not exist (or is a symbolic-link loop).
    ResourceAccessError
        The file lies outside ``sandbox``.
    UsageError
        Not JSON, not GeoJSON, no polygon or more than one, an unknown CRS, coordinates
        that do not fit the CRS, or an invalid polygon.
    """
    file = Path(path)
    if sandbox is not None:
        sandbox.check(file, "lot file")
    data = read_input_bytes(file, "lot file", MAX_LOT_FILE_BYTES)
    note_input(file)  # a batch records what each house was made from
    try:
        document = json.loads(data.decode("utf-8-sig"))
    except UnicodeDecodeError as error:
        raise UsageError(f"{file}: not UTF-8 text (byte {error.start} cannot be "
                         f"decoded)") from None
    except RecursionError:
        raise UsageError(f"{file}: the JSON is nested too deeply to be GeoJSON") from None
    except json.JSONDecodeError as error:
        raise UsageError(f"{file}: not a JSON file ({error.msg} at line {error.lineno} "
                         f"column {error.colno})") from None
    except ValueError as error:  # e.g. an integer of more than 4,300 digits
        raise UsageError(f"{file}: not a usable JSON file ({excerpt(str(error))})") from None
    polygons = _geojson_polygons(document, str(file))
    if len(polygons) != 1:
        raise UsageError(f"{file}: expected exactly one polygon, found {len(polygons)}"
                         + ("; a lot is one building: keep its outline only"
                            if len(polygons) > 1 else ""))
    return _georeferenced(document, polygons[0], str(file))


def _georeferenced(document: Any, polygon: Polygon, where: str) -> LotInput:
    """The lot of a GeoJSON ``polygon`` (source coordinates) in the plan frame."""
    if polygon.is_empty or len(polygon.exterior.coords) < 4:
        validate_lot(polygon, where)  # raises: fewer than 3 corners
    rings = [np.asarray(polygon.exterior.coords)] + [np.asarray(r.coords)
                                                     for r in polygon.interiors]
    if not all(np.isfinite(ring).all() for ring in rings):
        raise UsageError(f"{where}: every corner needs finite coordinates")
    frame = source_frame(document, rings[0], where)
    notes = []
    if frame.crs is None:
        local_crs, centre = None, None
        notes.append(f"read {where} in local metres ({frame.why})")
    else:
        rings, local_crs, centre = to_local_metres(rings, frame, where)
        notes.append(f"read {where} in {frame.name} ({frame.why}) and projected it to a "
                     f"transverse Mercator centred at {_lon_lat_text(centre)}")
    span = float(np.max(np.ptp(rings[0], axis=0)))
    if span > MAX_EXTENT:
        raise UsageError(f"{where}: the footprint spans {span:.4g} m; a lot must be at most "
                         f"{MAX_EXTENT:,.0f} m across")
    outline = Polygon(rings[0])
    if len(rings) > 1:
        holes = sum(Polygon(ring).area for ring in rings[1:])
        notes.append(f"warning: the footprint has {len(rings) - 1} hole"
                     f"{'s' if len(rings) > 2 else ''} ({holes:,.1f} m² in all); a lot is a "
                     f"filled outline, so the building covers {'them' if len(rings) > 2 else 'it'}")
    if not outline.is_valid or outline.area <= 0:
        validate_lot(outline, where)  # raises, naming the fault
    turn = main_direction(outline)
    turned = affinity.rotate(outline, -turn, origin=(0, 0), use_radians=True)
    if abs(math.degrees(turn)) >= 0.005:
        notes.append(f"turned the plan so x runs along the outline's main direction, "
                     f"{math.degrees(turn):.2f}° counter-clockwise from east")
    squared = square(turned)
    if squared is not None and squared.oblique:
        notes.append(f"warning: the outline is not rectilinear: {squared.oblique} of its "
                     f"{squared.edges} walls (the furthest {squared.oblique_deg:.1f}° off a "
                     f"right angle, more than the {SNAP_TOLERANCE_DEG:g}° squaring tolerance) "
                     f"are kept as drawn, the others squared (at most "
                     f"{squared.worst_deg:.2f}° off; corners moved by at most "
                     f"{squared.moved:.3f} m); make_floor cuts rooms parallel to the plan axes")
        turned = squared.polygon
    elif squared is not None:
        if squared.worst_deg > 1e-6:
            notes.append(f"squared the outline: its {squared.edges} walls were at most "
                         f"{squared.worst_deg:.2f}° off a right angle (tolerance "
                         f"{SNAP_TOLERANCE_DEG:g}°); corners moved by at most "
                         f"{squared.moved:.3f} m")
        turned = squared.polygon
    else:
        notes.append(f"warning: the outline is not rectilinear (a wall {edge_deviation(turned):.1f}° "
                     f"off a right angle, more than the {SNAP_TOLERANCE_DEG:g}° squaring "
                     f"tolerance), so it is kept as drawn; make_floor cuts rooms parallel to "
                     f"the plan axes")
    minu, _, _, maxv = turned.bounds
    # plan x = u - min u, plan z = max v - v: north (v) is -z in the y-up world; corners
    # to the millimetre (no footprint is more precise), so the plan does not depend on
    # the PROJ version's last digits
    plan = Polygon(np.round(np.column_stack([
        np.asarray(turned.exterior.coords)[:, 0] - minu,
        maxv - np.asarray(turned.exterior.coords)[:, 1]]), _PLAN_DECIMALS))
    origin = (minu * math.cos(turn) - maxv * math.sin(turn),
              minu * math.sin(turn) + maxv * math.cos(turn))
    georeference = Georeference(
        source_crs=None if frame.crs is None else _crs_name(frame),
        local_crs=local_crs, origin=origin,
        origin_lonlat=None if local_crs is None else frame_to_lonlat(local_crs, *origin),
        rotation_deg=math.degrees(turn))
    diagnostics = tuple(
        Diagnostic("warning", "lot", note.removeprefix("warning: ")) if note.startswith("warning: ")
        else Diagnostic("info", "lot", note) for note in notes)
    return LotInput(polygon=validate_lot(plan, where), text=where, georeference=georeference,
                    diagnostics=diagnostics)


def _crs_name(frame: SourceFrame) -> str:
    """The CRS as ``AUTHORITY:CODE`` when it has one, else its name."""
    authority = frame.crs.to_authority()
    return ":".join(authority) if authority else frame.name


def _lon_lat_text(point: tuple[float, float]) -> str:
    lon, lat = point
    return (f"{abs(lon):.6f}° {'E' if lon >= 0 else 'W'}, "
            f"{abs(lat):.6f}° {'N' if lat >= 0 else 'S'}")


def _geojson_polygons(document: Any, where: str) -> list[Polygon]:
    if not isinstance(document, dict) or "type" not in document:
        raise UsageError(f"{where}: not GeoJSON (no 'type'); expected a Polygon, a Feature "
                         f"or a FeatureCollection")
    kind = document["type"]
    if kind == "FeatureCollection":
        features = document.get("features", [])
        if not isinstance(features, list):
            raise UsageError(f"{where}: 'features' of a FeatureCollection must be a list, "
                             f"got {type(features).__name__}")
        return [p for feature in features for p in _geojson_polygons(feature, where)]
    if kind == "Feature":
        geometry = document.get("geometry")
        return [] if geometry is None else _geojson_polygons(geometry, where)
    if kind in ("Polygon", "MultiPolygon"):
        _check_positions(document.get("coordinates"), kind, where)
        try:
            geometry = geojson_shape(document)
        except (ValueError, TypeError, IndexError, AttributeError, KeyError) as error:
            raise UsageError(f"{where}: malformed {kind} coordinates "
                             f"({excerpt(str(error))})") from None
        return list(geometry.geoms) if isinstance(geometry, MultiPolygon) else [geometry]
    return []


def _check_positions(coordinates: Any, kind: str, where: str) -> None:
    """Every position of a Polygon/MultiPolygon is a pair of numbers ``[x, y]`` and there
    are at most :data:`MAX_LOT_VERTICES` of them.

    A lot is a plan footprint; a third coordinate (an altitude) has no meaning for it and
    would only fail later, far from the file.
    """
    depth = 3 if kind == "Polygon" else 4
    count = 0
    stack = [(coordinates, 1)]
    while stack:
        value, level = stack.pop()
        if not isinstance(value, list):
            raise UsageError(f"{where}: malformed {kind} coordinates (expected nested lists "
                             f"of [x, y] positions)")
        if level < depth:
            stack.extend((item, level + 1) for item in value)
            continue
        if len(value) != 2:
            raise UsageError(f"{where}: a lot position must be [x, y] (longitude, latitude "
                             f"or easting, northing), got "
                             f"{len(value)} coordinates"
                             + (" (a lot is a plan footprint: drop the height)"
                                if len(value) == 3 else ""))
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            raise UsageError(f"{where}: a lot position must be two numbers, got "
                             f"{excerpt(json.dumps(value))}")
        count += 1
        if count > MAX_LOT_VERTICES:
            raise BudgetError(f"{where}: the lot has more than {MAX_LOT_VERTICES:,} corners; "
                              f"simplify the footprint (docs/limits.md)")


def _parse_call(name: str, inner: str, text: str, scale: float) -> Polygon:
    if name.lower() == "rectangle":
        match = _RECT_ARGS.match(inner)
        if not match:
            raise UsageError(f"--lot {excerpt(text)}: rectangle takes two numbers, e.g. "
                             f"rectangle(14, 10)")
        return rectangle(float(match.group(1)) * scale, float(match.group(2)) * scale)
    points = _POINT.findall(inner)
    leftover = _POINT.sub("", inner).replace(",", "").strip()
    if not points or leftover:
        raise UsageError(f"--lot {excerpt(text)}: polygon takes corner points, e.g. "
                         f"polygon((0,0),(14,0),(14,10),(0,10))")
    return polygon_lot([(float(x) * scale, float(z) * scale) for x, z in points],
                       f"--lot {excerpt(text)}")


def read_lot(text: str, *, units: float = 1.0, base_dir: str | Path | None = None,
             sandbox: "Sandbox | None" = None) -> LotInput:
    """Read a ``--lot`` value (see the module docstring for the forms).

    Parameters
    ----------
    text:
        The option's value.
    units:
        Metres per grammar unit, for sizes written with the ``u`` suffix.
    base_dir:
        Folder a relative GeoJSON path is taken from (default: the working directory).
    sandbox:
        Folders a GeoJSON file may lie in (:mod:`cga.sandbox`); None reads any.

    Raises
    ------
    UsageError
        The text is none of the accepted forms, or the polygon is invalid.
    ResourceNotFoundError
        A ``.geojson``/``.json`` file that does not exist.
    """
    match = _SIZE.match(text) or _CALL.match(text)
    if match:
        suffix = (match.group(3) or "").lower()
        scale = units if suffix == "u" else 1.0
        try:
            if match.re is _SIZE:
                polygon = rectangle(float(match.group(1)) * scale, float(match.group(2)) * scale)
            else:
                polygon = _parse_call(match.group(1), match.group(2), text, scale)
        except UsageError as error:
            if suffix != "u":
                raise
            raise UsageError(f"{error} (--lot {excerpt(text)} read in grammar units of "
                             f"{units:g} m)") from None
        return LotInput(polygon=polygon, text=text, unit="grammar" if suffix == "u" else "m",
                        unit_stated=bool(suffix))
    if text.lower().endswith((".geojson", ".json")):
        path = Path(text)
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        return read_geojson(path, sandbox=sandbox)
    raise UsageError(f"--lot {excerpt(text)}: {_expected()}")


def parse_lot(text: str, *, units: float = 1.0, base_dir: str | Path | None = None,
              sandbox: "Sandbox | None" = None) -> Polygon:
    """The plan polygon of a ``--lot`` value (see :func:`read_lot`)."""
    return read_lot(text, units=units, base_dir=base_dir, sandbox=sandbox).polygon


def lot_from_call(name: str, args: Sequence[Any], span: Span, units: float) -> Polygon:
    """The lot of a grammar's ``Lot:`` line from its evaluated arguments.

    ``rectangle(w, d)`` takes two numbers, ``polygon(p1, p2, ...)`` takes ``(x, z)``
    pairs; both in grammar units, scaled by ``units`` to metres.

    Raises
    ------
    DerivationError
        Unknown shape, wrong arguments or an invalid polygon, at ``span``.
    """
    def number(value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise DerivationError(f"Lot: {name}() takes numbers, got {value!r}", span)
        return float(value) * units

    try:
        if name == "rectangle":
            if len(args) != 2:
                raise DerivationError(f"Lot: rectangle takes 2 numbers (width, depth), got "
                                      f"{len(args)}", span)
            return rectangle(number(args[0]), number(args[1]))
        if name == "polygon":
            if not all(isinstance(a, tuple) and len(a) == 2 for a in args):
                raise DerivationError("Lot: polygon takes (x, z) corner pairs, e.g. "
                                      "polygon((0,0),(14,0),(14,10),(0,10))", span)
            return polygon_lot([(number(x), number(z)) for x, z in args], "Lot: polygon")
    except (UsageError, BudgetError) as error:
        read = "" if units == 1 else f" (Lot: is in grammar units of {units:g} m)"
        raise DerivationError(f"{error}{read}", span) from None
    raise DerivationError(f"Lot: unknown shape '{name}'", span,
                          hint="use rectangle(width, depth) or polygon((x,z), ...)")
