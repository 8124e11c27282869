"""Real-world footprints: from a GeoJSON file's coordinates to plan metres, and back.

GeoJSON (RFC 7946) stores WGS84 longitude/latitude; GIS tools also write projected
coordinate reference systems (CRS) named by the older ``crs`` member (GeoJSON 2008),
e.g. ``"urn:ogc:def:crs:EPSG::25832"`` (UTM) or ``EPSG:3857`` (web Mercator, whose
lengths are off by 1/cos(latitude)). Whatever the CRS, the footprint is re-projected
with pyproj to a transverse Mercator centred on it: over a building's extent its scale
error is below 10⁻⁶, so plan lengths and areas are true ground metres (Snyder 1987,
*Map Projections: A Working Manual*, §8).

A file without a ``crs`` member is WGS84, as RFC 7946 says, when it could be: every
coordinate a longitude/latitude and the footprint less than :data:`GEOGRAPHIC_EXTENT`
across (a degree is 111 km; a building is far smaller, and a footprint drawn in metres
is far larger than a degree). Otherwise its coordinates are local metres, as cga has
always read them.

The plan frame (:class:`Georeference`): plan ``x`` along the footprint's main direction
(:func:`cga.rectify.main_direction`), plan ``z`` towards the right of it seen from above
(the world is y-up and right-handed, so north is −z when ``x`` is east), the bounding box's
corner at the plan origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import UsageError, excerpt

__all__ = ["GEOGRAPHIC_EXTENT", "WGS84", "Georeference", "SourceFrame", "source_frame",
           "to_local_metres", "frame_to_lonlat"]

GEOGRAPHIC_EXTENT = 1.0
"""A footprint without a ``crs`` member that spans less than this many coordinate units
(and whose coordinates are all valid longitudes/latitudes) is read as WGS84 degrees."""

WGS84 = "OGC:CRS84"
"""WGS84 longitude/latitude in that axis order: the CRS of RFC 7946 GeoJSON."""


@dataclass(frozen=True)
class SourceFrame:
    """How a file's coordinates are read: ``crs`` (a pyproj ``CRS``; None for local
    metres) and a sentence saying why, for the build's diagnostics."""

    crs: Any
    name: str
    why: str


@dataclass(frozen=True)
class Georeference:
    """Where the plan lies in the world.

    ``source_crs`` is the file's CRS (None: local metres), ``local_crs`` the PROJ string
    of the transverse Mercator the footprint was projected to (None: local metres, used
    as they are), ``origin`` the plan origin in that frame (easting, northing; metres)
    and ``origin_lonlat`` in WGS84 (None for local metres). ``rotation_deg`` is the angle
    from the frame's east axis to plan ``+x``, counter-clockwise seen from above. A plan
    point ``(x, z)`` lies at easting ``E0 + x·cos r + z·sin r``, northing
    ``N0 + x·sin r − z·cos r``.
    """

    source_crs: str | None
    local_crs: str | None
    origin: tuple[float, float]
    origin_lonlat: tuple[float, float] | None
    rotation_deg: float

    def plan_to_frame(self, x: float, z: float) -> tuple[float, float]:
        """The (easting, northing) of plan point ``(x, z)`` in the local frame."""
        r = math.radians(self.rotation_deg)
        e0, n0 = self.origin
        return (e0 + x * math.cos(r) + z * math.sin(r), n0 + x * math.sin(r) - z * math.cos(r))

    def to_dict(self) -> dict[str, Any]:
        """The scene JSON's ``georeference`` (cga/schema/scene.schema.json)."""
        return {
            "source_crs": self.source_crs,
            "local_crs": self.local_crs,
            "origin": [float(self.origin[0]), float(self.origin[1])],
            "origin_lonlat": (None if self.origin_lonlat is None
                              else [float(v) for v in self.origin_lonlat]),
            "rotation_deg": float(self.rotation_deg),
            "plan_to_local": "easting = origin[0] + x*cos(r) + z*sin(r), "
                             "northing = origin[1] + x*sin(r) - z*cos(r), r = rotation_deg",
        }


def _crs(text: str, where: str) -> Any:
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    try:
        return CRS.from_user_input(text)
    except CRSError:
        raise UsageError(f"{where}: unknown crs {excerpt(text)}; name it as EPSG:25832 or "
                         f"urn:ogc:def:crs:EPSG::25832, or leave the crs member out for "
                         f"WGS84 longitude/latitude (RFC 7946)") from None


def source_frame(document: Any, points: np.ndarray, where: str) -> SourceFrame:
    """The CRS of a GeoJSON document whose footprint has corners ``points`` (n × 2).

    Raises
    ------
    UsageError
        A ``crs`` member that is not ``{"type": "name", "properties": {"name": ...}}``,
        names no known CRS or a CRS that is neither geographic nor projected, or
        coordinates that cannot be longitude/latitude in a geographic CRS.
    """
    member = document.get("crs") if isinstance(document, dict) else None
    span = points.max(axis=0) - points.min(axis=0)
    if member is None:
        if _lon_lat(points) and span.max() < GEOGRAPHIC_EXTENT:
            return SourceFrame(_crs(WGS84, where), "WGS84 longitude/latitude",
                               "a GeoJSON file without a crs member, RFC 7946")
        return SourceFrame(None, "local metres",
                           f"no crs member, and the footprint spans {span[0]:g} × {span[1]:g}, "
                           f"more than a building's longitude/latitude could")
    name = member.get("properties", {}).get("name") if isinstance(member, dict) else None
    if not (isinstance(member, dict) and member.get("type") == "name" and isinstance(name, str)):
        raise UsageError(f"{where}: the crs member must be {{\"type\": \"name\", \"properties\": "
                         f"{{\"name\": \"EPSG:25832\"}}}}; got {excerpt(repr(member))}")
    crs = _crs(name, where)
    if crs.is_geographic:
        if not _lon_lat(points):
            raise UsageError(f"{where}: the crs {excerpt(name)} is longitude/latitude, but the "
                             f"coordinates reach {np.abs(points).max():g}; are they metres "
                             f"of a projected CRS? Name that CRS in the crs member")
    elif not crs.is_projected:
        raise UsageError(f"{where}: the crs {excerpt(name)} is neither longitude/latitude nor "
                         f"a projected CRS; give the footprint in one of those")
    return SourceFrame(crs, crs.name or name, "the file's crs member")


def _lon_lat(points: np.ndarray) -> bool:
    return bool(np.all(np.abs(points[:, 0]) <= 180) and np.all(np.abs(points[:, 1]) <= 90))


def to_local_metres(rings: list[np.ndarray], frame: SourceFrame, where: str
                    ) -> tuple[list[np.ndarray], str, tuple[float, float]]:
    """``rings`` (source coordinates; the first is the exterior) projected to a
    transverse Mercator centred on the exterior's bounding box: the rings in metres
    (easting, northing), the frame's PROJ string and its centre (longitude, latitude).

    Raises
    ------
    UsageError
        A point the projection cannot map (outside the CRS's area of use).
    """
    from pyproj import CRS, Transformer

    to_degrees = Transformer.from_crs(frame.crs, CRS.from_user_input(WGS84), always_xy=True)
    lon, lat = to_degrees.transform(rings[0][:, 0], rings[0][:, 1])
    if not (np.all(np.isfinite(lon)) and np.all(np.isfinite(lat))):
        raise UsageError(f"{where}: a corner lies outside the area {frame.name} can map")
    centre = ((float(np.min(lon)) + float(np.max(lon))) / 2,
              (float(np.min(lat)) + float(np.max(lat))) / 2)
    local = (f"+proj=tmerc +lat_0={centre[1]:.9f} +lon_0={centre[0]:.9f} +k=1 +x_0=0 "
             f"+y_0=0 +ellps=WGS84 +units=m +no_defs")
    to_local = Transformer.from_crs(frame.crs, CRS.from_proj4(local), always_xy=True)
    projected = []
    for ring in rings:
        east, north = to_local.transform(ring[:, 0], ring[:, 1])
        points = np.column_stack([east, north])
        if not np.all(np.isfinite(points)):
            raise UsageError(f"{where}: a corner lies outside the area {frame.name} can map")
        projected.append(points)
    return projected, local, centre


def frame_to_lonlat(local_crs: str, east: float, north: float) -> tuple[float, float]:
    """The WGS84 (longitude, latitude) of a point of a local frame from
    :func:`to_local_metres`."""
    from pyproj import CRS, Transformer

    back = Transformer.from_crs(CRS.from_proj4(local_crs), CRS.from_user_input(WGS84),
                                always_xy=True)
    lon, lat = back.transform(east, north)
    return float(lon), float(lat)
