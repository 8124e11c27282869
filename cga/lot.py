"""The lot: the footprint polygon a derivation starts from.

A lot comes from the command line (``--lot``), from the grammar's ``Lot:`` line, or is
the default rectangle. Every form ends as a valid shapely :class:`~shapely.geometry.Polygon`
in plan coordinates ``(x, z)``, metres, exterior counter-clockwise in those coordinates
(shapely's ``orient(sign=1)``), not self-intersecting, with positive area.

Accepted ``--lot`` forms (metres)::

    14x10                                   a 14 m × 10 m rectangle at the origin
    rectangle(14, 10)                       the same
    "polygon((0,0),(14,0),(14,6),(8,6),(8,10),(0,10))"
    footprint.geojson                       a GeoJSON Polygon, a Feature with one, or a
                                            FeatureCollection holding exactly one polygon
                                            (coordinates in metres, x east → plan x,
                                            y north → plan z)

The grammar's ``Lot: rectangle(w, d)`` / ``Lot: polygon(...)`` uses the same shapes in
grammar units; :func:`lot_from_call` scales them by ``units``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from shapely.geometry import MultiPolygon, Polygon, shape as geojson_shape
from shapely.geometry.polygon import orient
from shapely.validation import explain_validity

from .errors import BudgetError, DerivationError, Span, UsageError, excerpt
from .provenance import note_input
from .textfiles import read_input_bytes

if TYPE_CHECKING:  # pragma: no cover
    from .sandbox import Sandbox

__all__ = ["DEFAULT_LOT", "MAX_EXTENT", "MAX_LOT_VERTICES", "MAX_LOT_FILE_BYTES", "LOT_FORMATS", "validate_lot", "rectangle", "polygon_lot",
           "parse_lot", "load_geojson", "lot_from_call"]

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

LOT_FORMATS = ('14x10 (width x depth in metres)', '"rectangle(14, 10)"',
               '"polygon((0,0),(14,0),(14,10),(0,10))"', "a .geojson file with one polygon")
"""The ``--lot`` forms, as listed in error messages."""

_NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
_SIZE = re.compile(rf"^\s*({_NUMBER})\s*[xX×*]\s*({_NUMBER})\s*$")
_CALL = re.compile(r"^\s*(rectangle|polygon)\s*\((.*)\)\s*$", re.IGNORECASE | re.DOTALL)
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
                         f"{width:g} x {depth:g}")
    return validate_lot(Polygon([(0, 0), (width, 0), (width, depth), (0, depth)]),
                      f"rectangle {width:g} x {depth:g}")


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


def load_geojson(path: str | Path, *, sandbox: "Sandbox | None" = None) -> Polygon:
    """The single polygon of a GeoJSON file (Polygon, Feature or FeatureCollection).

    ``sandbox``, when given, holds the folders the file may lie in (:mod:`cga.sandbox`).

    Raises
    ------
    ResourceNotFoundError
        The file does not exist (or is a symbolic-link loop).
    ResourceAccessError
        The file lies outside ``sandbox``.
    UsageError
        Not JSON, not GeoJSON, no polygon or more than one, or an invalid polygon.
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
        raise UsageError(f"{file}: expected exactly one polygon, found {len(polygons)}")
    return validate_lot(polygons[0], str(file))


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
            raise UsageError(f"{where}: a lot position must be [x, y] in metres, got "
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


def _parse_call(name: str, inner: str, text: str) -> Polygon:
    if name.lower() == "rectangle":
        match = _RECT_ARGS.match(inner)
        if not match:
            raise UsageError(f"--lot {excerpt(text)}: rectangle takes two numbers, e.g. "
                             f"rectangle(14, 10)")
        return rectangle(float(match.group(1)), float(match.group(2)))
    points = _POINT.findall(inner)
    leftover = _POINT.sub("", inner).replace(",", "").strip()
    if not points or leftover:
        raise UsageError(f"--lot {excerpt(text)}: polygon takes corner points, e.g. "
                         f"polygon((0,0),(14,0),(14,10),(0,10))")
    return polygon_lot([(float(x), float(z)) for x, z in points], f"--lot {excerpt(text)}")


def parse_lot(text: str, *, base_dir: str | Path | None = None,
              sandbox: "Sandbox | None" = None) -> Polygon:
    """Parse a ``--lot`` value (see the module docstring for the forms).

    Parameters
    ----------
    text:
        The option's value.
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
    match = _SIZE.match(text)
    if match:
        return rectangle(float(match.group(1)), float(match.group(2)))
    match = _CALL.match(text)
    if match:
        return _parse_call(match.group(1), match.group(2), text)
    if text.lower().endswith((".geojson", ".json")):
        path = Path(text)
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        return load_geojson(path, sandbox=sandbox)
    raise UsageError(f"--lot {excerpt(text)}: {_expected()}")


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
        raise DerivationError(str(error), span) from None
    raise DerivationError(f"Lot: unknown shape '{name}'", span,
                          hint="use rectangle(width, depth) or polygon((x,z), ...)")
