"""Sizing a stair and placing a building's stair core (DESIGN §12).

A storey of height ``H`` is climbed in ``n = ceil(H / max_rise)`` risers (even for a U
stair, so both flights match) of ``rise = H / n``; the going follows Blondel's step rule
``2 · rise + going ≈ 0.63 m``, never less than ``min_going``. A U stair (half landing)
runs two flights side by side with a well between them; a straight stair one flight.

The core is the rectangle that holds the floor landing, the flight(s) and the half (or
top) landing, plus the walls around it. It stands along the footprint's boundary or
along a corridor, with its landing opening onto the corridor where it can, so the stair
is reached from circulation (DESIGN §11, §12); in a bay too shallow to leave a room
beside it, it fills the bay. The place is chosen once per building from the build seed
and the footprint (:func:`core_for_storey`), so every storey of the stack reserves the
same rectangle before it is partitioned; the MSU seed (procedural-interiors-msu.txt)
likewise puts "a stair on every floor but the last".
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient
from shapely.ops import unary_union

from cga.errors import DerivationError
from cga.model import Point2, StairCore
from cga.randomness import stream

__all__ = ["STAIR_KINDS", "StairParams", "design_risers", "going_for", "place_core",
           "core_for_storey"]

STAIR_KINDS = ("U", "straight", "none")
"""Values of make_floor's ``stair``: a U stair with a half landing, one straight flight,
or no stair."""

_GRID = 0.01  # m: core sizes and positions on the BSP's 1 cm grid
_STEP = 0.5  # m: spacing of the candidate positions along an edge
_MAX_POSITIONS = 24  # candidate positions per edge at most
_DOOR_MARGIN = 0.1  # m: clear wall each side of a door (roomtyping.doors.DOOR_MARGIN)
_FRONTAGE_SHARE = 0.4
"""Most of a free part's corridor frontage a core takes before a place that takes less
ranks above it (:func:`_starves`)."""


@dataclass(frozen=True)
class StairParams:
    """A stair's parameters as the grammar gives them (metres)."""

    kind: Literal["straight", "U"] = "U"
    width: float = 1.0
    max_rise: float = 0.19
    min_going: float = 0.25
    well: float = 0.2

    def check(self) -> None:
        """Raise :class:`DerivationError` for parameters no stair can meet."""
        if self.kind not in ("straight", "U"):
            raise DerivationError(
                f"stair must be one of 'U', 'straight', 'none', got {self.kind!r}")
        if not 0.5 <= self.width <= 5.0:
            raise DerivationError(f"stair_width must be between 0.5 and 5 m, got {self.width:g}")
        if not 0.1 <= self.max_rise <= 0.25:
            raise DerivationError(
                f"max_rise must be between 0.1 and 0.25 m, got {self.max_rise:g}")
        if not 0.15 <= self.min_going <= 0.5:
            raise DerivationError(
                f"min_going must be between 0.15 and 0.5 m, got {self.min_going:g}")


def design_risers(height: float, max_rise: float, kind: str) -> tuple[int, float]:
    """``(risers, rise)`` climbing ``height`` with no riser above ``max_rise`` (an even
    count for a U stair)."""
    n = math.ceil(height / max_rise - 1e-9)
    if kind == "U" and n % 2:
        n += 1
    return n, height / n


def going_for(rise: float, min_going: float) -> float:
    """Blondel's rule ``2 · rise + going = 0.63 m``, at least ``min_going``, rounded up
    to the millimetre."""
    return max(min_going, math.ceil((0.63 - 2 * rise) * 1000 - 1e-6) / 1000)


def _landing_depth(params: StairParams, door_width: float, wall: float) -> float:
    """Deep enough to step off the stair (its width) and for a door along its side."""
    return max(params.width, door_width + 2 * _DOOR_MARGIN + wall)


def _up(value: float) -> float:
    return math.ceil(value / _GRID - 1e-6) * _GRID


def place_core(footprint: Polygon, storey_height: float, storeys: int, params: StairParams, *,
               wall: float, door_width: float, min_width: float,
               rng: np.random.Generator, corridors: Sequence[Polygon] = ()) -> StairCore:
    """Place a stair core against the footprint's boundary.

    Parameters
    ----------
    footprint
        The storey's footprint (counter-clockwise, rectilinear or convex).
    storey_height
        Floor-to-floor height the stair climbs (m).
    storeys
        How many storeys the core serves.
    params
        Kind, width, maximum rise, minimum going.
    wall, door_width, min_width
        Wall thickness, door width and the least room width of the storey (m).
    rng
        Chooses among the best places.
    corridors
        The storey's corridors and halls (DESIGN §11): the core keeps clear of them and,
        where it can, its landing opens onto one.

    Returns
    -------
    StairCore

    Raises
    ------
    DerivationError
        No edge of the footprint takes the core with rooms of ``min_width`` left around it.

    Notes
    -----
    Candidates lie along every axis-aligned edge of the footprint and of the corridors
    (on the side away from the corridor) that is long enough for the core: flush with
    either end or at least ``min_width`` from it, every 0.5 m, or flush against a
    corridor crossing the edge, the landing at either end; a core whose far side would
    leave a strip narrower than ``min_width`` is also tried stretched across it
    (:func:`_breadths`). A candidate is kept when the core
    lies inside the footprint and off the corridors, splits the free floor into no more
    parts, leaves no new part narrower than ``min_width``, and the landing's long side
    faces the inside (it takes the door). Ranked: the landing touches a corridor over a
    door width, the core takes no more than :data:`_FRONTAGE_SHARE` of the corridor
    frontage of the free part it stands in (:func:`_starves`), it is not stretched, it
    stands against an outer wall, its landing is nearest the footprint's centre (ties in
    the order the candidates are made); the pick is drawn from ``rng`` among the best
    three that are as good as the best on the first two.

    Only the best three kept candidates matter, so every candidate is ranked first and
    the costly tests (off the corridors, :meth:`_Room.fits`: two polygon overlays and an
    opening) are made in rank order, once per rectangle, until three pass: the same
    pick as testing them all, at a fraction of the tests. The rankings' own geometry is
    computed for all candidates at once. O(edges × positions) shapely operations, once
    per footprint in a process (:func:`_best_places`).
    """
    params.check()
    risers, rise = design_risers(storey_height, params.max_rise, params.kind)
    going = going_for(rise, params.min_going)
    depth = _landing_depth(params, door_width, wall)
    core = StairCore(polygon=Polygon(), origin=(0.0, 0.0), u=(1.0, 0.0), v=(0.0, 1.0),
                     kind=params.kind, width=params.width, well=params.well,
                     landing_depth=depth, risers=risers, rise=rise, going=going,
                     storeys=storeys)
    stair_breadth = core.interior_width + 2 * wall
    length = _up(core.interior_length + 2 * wall)
    breadth = _up(stair_breadth)
    found, best = _best_places(footprint, tuple(corridors), _Sizes(
        length=length, breadth=breadth, stair_breadth=stair_breadth, depth=depth,
        interior_width=core.interior_width, wall=wall, door_width=door_width,
        min_width=min_width))
    if not best:
        minx, minz, maxx, maxz = footprint.bounds
        raise DerivationError(
            f"no place for a {params.kind} stair core of {length:.2f} m x {breadth:.2f} m in a "
            f"{maxx - minx:.4g} m x {maxz - minz:.4g} m footprint with rooms at least "
            f"{min_width:g} m wide around it",
            hint="give the building a larger lot, a narrower stair (stair_width), "
                 "or stair = \"none\"")
    k = best[int(rng.integers(len(best)))]
    origin, u, v = found.origin[k], found.u[k], found.v[k]
    return replace(core, polygon=orient(found.rects[found.rect[k]], sign=1.0),
                   origin=(float(origin[0]), float(origin[1])), u=(float(u[0]), float(u[1])),
                   v=(float(v[0]), float(v[1])))


@dataclass(frozen=True)
class _Sizes:
    """The sizes (m) a core's places depend on besides the footprint and corridors."""

    length: float
    breadth: float
    stair_breadth: float
    depth: float
    interior_width: float
    wall: float
    door_width: float
    min_width: float


_PLACES: dict[tuple[bytes, tuple[bytes, ...], _Sizes], tuple["_Candidates", tuple[int, ...]]] = {}
_PLACES_KEPT = 16
"""Footprints whose best places a process keeps (:func:`_best_places`)."""


def _best_places(footprint: Polygon, corridors: tuple[Polygon, ...], sizes: _Sizes
                 ) -> tuple["_Candidates", tuple[int, ...]]:
    """The candidates of :func:`place_core` and the best three that pass (by index,
    best first; fewer when fewer pass, none when no place does), kept per process by
    the footprint's and corridors' exact coordinates and the sizes.

    They depend on nothing else, not on the seed: a batch builds one grammar's lot
    seed after seed, and each house would rank the same few hundred places again
    (about 5 % of a house's build without the checks). Only the draw among them is the
    seed's.

    Keyed by the geometries' WKB, not by the geometries: shapely calls two polygons
    equal whatever vertex their rings start at and whichever way they turn, and those
    order the candidates, which breaks ties between equally good places."""
    key = (footprint.wkb, tuple(c.wkb for c in corridors), sizes)
    kept = _PLACES.pop(key, None)
    if kept is None:
        kept = _rank_places(footprint, corridors, sizes)
        if len(_PLACES) >= _PLACES_KEPT:
            _PLACES.pop(next(iter(_PLACES)))
    _PLACES[key] = kept  # most recently used last
    return kept


def _rank_places(footprint: Polygon, corridors: tuple[Polygon, ...], sizes: _Sizes
                 ) -> tuple["_Candidates", tuple[int, ...]]:
    """:func:`_best_places`, computed."""
    length, breadth, min_width = sizes.length, sizes.breadth, sizes.min_width
    free = _free_region(footprint, corridors)
    room = _Room.of(footprint, free, min_width)
    corners, along, across = _sites(footprint, corridors, length, min_width)
    reaches = _reaches(room.edges, corners, along, across, length, breadth + min_width)
    found = _Candidates.of(corners, along, across, reaches, length=length, breadth=breadth,
                           min_width=min_width, stair_breadth=sizes.stair_breadth,
                           wall=sizes.wall)
    # the landing's long side is an outer wall: no door there
    faces_in = shapely.contains(footprint, shapely.points(found.at(sizes.depth / 2,
                                                                   sizes.stair_breadth)))
    keys = _ranks(found, np.flatnonzero(faces_in), footprint, corridors, free,
                  depth=sizes.depth, wall=sizes.wall, door_width=sizes.door_width,
                  interior_width=sizes.interior_width)
    best: list[int] = []
    passes: dict[int, bool] = {}
    for k in sorted(keys, key=keys.__getitem__):
        r = int(found.rect[k])
        if r not in passes:
            rect = found.rects[r]
            passes[r] = (not any(rect.intersects(c) and rect.intersection(c).area > 1e-9
                                 for c in corridors) and room.fits(rect))
        if passes[r]:
            if best and keys[k][:2] != keys[best[0]][:2]:
                break  # the draw is among places as good on the landing and the frontage
            best.append(k)
            if len(best) == 3:
                break
    return found, tuple(best)


@dataclass(frozen=True)
class _Candidates:
    """The candidate cores of :func:`place_core`, one row each in generation order: the
    index of the core's rectangle in ``rects`` and its stair's frame (``origin``, ``u``,
    ``v`` of :class:`StairCore`). ``stretched`` tells, by rectangle, a core deeper than
    its stair's breadth."""

    rects: np.ndarray
    stretched: np.ndarray
    rect: np.ndarray
    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray

    @classmethod
    def of(cls, corners: np.ndarray, along: np.ndarray, across: np.ndarray,
           reaches: list[float], *, length: float, breadth: float, min_width: float,
           stair_breadth: float, wall: float) -> "_Candidates":
        """The cores standing at the sites ``corners`` (their edges' directions
        ``along``, normals ``across``, the free region's ``reaches``), each as deep as
        :func:`_breadths` tries, and on each rectangle the stair with its landing at
        either end and against each side :func:`_breadths` gives."""
        site: list[int] = []
        deep: list[float] = []
        rect: list[int] = []
        flip: list[bool] = []
        hug: list[float] = []
        for k, reach in enumerate(reaches):
            for breadth_k, hugs in _breadths(reach, breadth, min_width, stair_breadth):
                for flip_k, hug_k in itertools.product((False, True), hugs):
                    rect.append(len(site))
                    flip.append(flip_k)
                    hug.append(hug_k)
                site.append(k)
                deep.append(breadth_k)
        sites = np.array(site, dtype=np.intp)
        d, n, corner = along[sites], across[sites], corners[sites]
        depths = np.array(deep)[:, None]
        # rounded, so a core flush with a corner meets it exactly (3.01 + 5.39 is
        # 8.399999999999999 in floating point)
        rects = shapely.polygons(np.round(np.stack(
            [corner, corner + d * length, corner + d * length + n * depths, corner + n * depths],
            axis=1), 9))
        on = np.array(rect, dtype=np.intp)
        flips = np.array(flip, dtype=bool)
        d, n = d[on], n[on]
        offset = np.where(flips, length - wall, wall)[:, None]
        origin = corner[on] + d * offset + n * (np.array(hug) + wall)[:, None]
        return cls(rects=rects, stretched=np.array(deep) > breadth, rect=on, origin=origin,
                   u=np.where(flips[:, None], -d, d), v=n)

    def at(self, u: float, v: float) -> np.ndarray:
        """Every candidate's plan point at core coordinates ``(u, v)``
        (:meth:`StairCore.at`)."""
        return self.origin + u * self.u + v * self.v


def _ranks(found: _Candidates, keep: np.ndarray, footprint: Polygon,
           corridors: Sequence[Polygon], free: Polygon | MultiPolygon, *, depth: float,
           wall: float, door_width: float,
           interior_width: float) -> dict[int, tuple[bool, bool, bool, bool, float]]:
    """The ranking keys of the candidates ``keep``, by candidate: the landing does not
    open onto a corridor over a door width, the core starves its part of corridor
    frontage (:func:`_starves`), it is stretched, it does not touch the outer wall, and
    its landing's distance to the footprint's centre (lowest first).

    The overlays run only where they can meet anything: a landing whose bounding box
    is more than a millimetre off a corridor's, or a core that does not touch the outer
    wall, meets it in nothing (length 0)."""
    onto = np.zeros(len(keep), dtype=bool)
    if corridors:
        # the landing end of the core out to its walls' centre lines (StairCore.rect)
        ends = np.stack([found.at(a, b)[keep] for a, b in (
            (-wall, -wall), (depth, -wall), (depth, interior_width + wall),
            (-wall, interior_width + wall))], axis=1)
        low, high = ends.min(axis=1), ends.max(axis=1)
        for c in corridors:
            x0, z0, x1, z1 = c.bounds
            near = np.flatnonzero((low[:, 0] <= x1 + 1e-3) & (high[:, 0] >= x0 - 1e-3)
                                  & (low[:, 1] <= z1 + 1e-3) & (high[:, 1] >= z0 - 1e-3))
            strips = shapely.buffer(shapely.orient_polygons(shapely.polygons(ends[near])), 1e-6,
                                    quad_segs=16)
            onto[near] |= shapely.length(shapely.intersection(strips, c.boundary)) >= door_width
    ring = footprint.exterior
    shapely.prepare(ring)
    touching = np.flatnonzero(shapely.intersects(found.rects, ring))
    walled = np.zeros(len(found.rects), dtype=bool)
    walled[touching] = shapely.length(shapely.intersection(found.rects[touching], ring)) > 1e-6
    landing = shapely.points(found.at(depth / 2, interior_width / 2)[keep])
    distance = shapely.distance(landing, footprint.centroid)
    rect = found.rect[keep]
    starves = _starves(found.rects, free, corridors)
    return {int(k): (not o, bool(starves[r]), bool(found.stretched[r]), not walled[r],
                     float(dist))
            for k, o, r, dist in zip(keep, onto.tolist(), rect, distance)}


def _starves(rects: np.ndarray, free: Polygon | MultiPolygon,
             corridors: Sequence[Polygon]) -> np.ndarray:
    """By rectangle: the core would run along more than :data:`_FRONTAGE_SHARE` of the
    corridor frontage of the part of the ``free`` region (:func:`_free_region`) it stands
    in. Every room of that part is cut to touch the corridor, so a core laid along a
    short hall leaves them a few metres of it and the part cannot be divided (a room of
    35–48 m² beside a 10 m hall)."""
    starves = np.zeros(len(rects), dtype=bool)
    if not corridors:
        return starves
    halls = shapely.buffer(unary_union([c.boundary for c in corridors]), 1e-6)
    parts = shapely.get_parts(free)
    frontage = shapely.length(shapely.intersection(shapely.boundary(parts), halls))
    taken = shapely.length(shapely.intersection(shapely.boundary(rects), halls))
    tree = shapely.STRtree(parts)
    rect, part = tree.query(shapely.point_on_surface(rects), predicate="within")
    starves[rect] = taken[rect] > _FRONTAGE_SHARE * frontage[part] + 1e-6
    return starves


def _positions(edge: float, length: float, min_width: float) -> list[float]:
    """Offsets of the core along an edge: flush with either end, or ``min_width`` clear
    of both, every :data:`_STEP` (at most :data:`_MAX_POSITIONS` of them, spread evenly,
    so a kilometre-long edge costs no more than a house's)."""
    out = {0.0, round(edge - length, 6)}
    free = edge - length - 2 * min_width
    if free >= -1e-9:
        count = min(_MAX_POSITIONS, int(free / _STEP + 1e-9) + 1)
        step = free / (count - 1) if count > 1 else 0.0
        for k in range(count):
            out.add(round(math.floor((min_width + k * step) / _GRID + 1e-6) * _GRID, 6))
    return sorted(out)


def _beside_corridors(a: Point2, d: np.ndarray, edge: float, length: float,
                      corridors: Sequence[Polygon]) -> list[float]:
    """Offsets along the edge from ``a`` (direction ``d``, ``edge`` long) at which a core
    ``length`` long stands flush against the side of a corridor that crosses the edge:
    its end then opens onto the corridor across it, and the rooms beyond keep the
    corridor's length (the 0.5 m steps of :func:`_positions` miss that spot)."""
    out = []
    for corridor in corridors:
        coords = np.asarray(corridor.exterior.coords) - np.asarray(a)
        along = coords @ d
        across = coords @ np.array([-d[1], d[0]])
        if across.min() > 1e-6:
            continue  # the corridor does not reach this edge
        for s in (round(float(along.max()), 6), round(float(along.min()) - length, 6)):
            if -1e-9 <= s <= edge - length + 1e-9:
                out.append(s)
    return out


def _sites(footprint: Polygon, corridors: Sequence[Polygon], length: float,
           min_width: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(corners, along, across)``, one row per candidate position: the corner the core
    stands at, the unit direction of its edge, and the normal into the free side, over
    the axis-aligned edges (:func:`_edges_to_stand_on`) at least ``length`` long, at the
    offsets :func:`_positions` gives."""
    corners: list[np.ndarray] = []
    along: list[np.ndarray] = []
    across: list[np.ndarray] = []
    for a, b in _edges_to_stand_on(footprint, corridors):
        edge = math.dist(a, b)
        d = np.subtract(b, a) / edge if edge > 0 else np.zeros(2)
        if edge < length - 1e-9 or min(abs(d[0]), abs(d[1])) > 1e-9:
            continue
        n = np.array([-d[1], d[0]])  # the inside lies to the left of a CCW edge
        for s in _positions(edge, length, min_width) + _beside_corridors(a, d, edge, length,
                                                                         corridors):
            corners.append(np.asarray(a) + d * s)
            along.append(d)
            across.append(n)
    if not corners:
        return np.empty((0, 2)), np.empty((0, 2)), np.empty((0, 2))
    return np.array(corners), np.array(along), np.array(across)


def _breadths(reach: float, breadth: float, min_width: float,
              stair_breadth: float) -> list[tuple[float, tuple[float, ...]]]:
    """``(breadth, offsets)`` to try for a core whose free region runs ``reach`` from
    its edge (:func:`_reaches`).

    The core is its stair's breadth deep, or, where the free region beyond would be a
    strip narrower than a room (a corridor's bay of offices 4 m deep and a 2.5 m
    core), as deep as the bay: the rest of the bay becomes a lobby of the stair hall
    instead of a sliver. A stretched core's stair stands against either long side
    (``offsets`` from the edge), so its landing can face the corridor on either side.
    """
    if breadth + 1e-6 < reach < breadth + min_width - 1e-6:
        return [(breadth, (0.0,)), (reach, (0.0, reach - stair_breadth))]
    return [(breadth, (0.0,))]


def _reaches(edges: shapely.Geometry, corners: np.ndarray, along: np.ndarray,
             across: np.ndarray, length: float, limit: float) -> list[float]:
    """How far the free region (whose boundary is ``edges``) runs from each site's edge
    along its normal ``across`` (at most ``limit``), the least over the core's two ends
    and middle. Only the rays that cross ``edges`` (best prepared) are overlaid."""
    t = np.array([0.01, 0.5, 0.99])
    starts = (corners[:, None] + along[:, None] * (t * length)[:, None]
              + across[:, None] * 1e-4)
    lines = shapely.linestrings(np.stack([starts, starts + across[:, None] * limit], axis=2)
                                .reshape(-1, 2, 2))
    crossing = np.flatnonzero(shapely.intersects(lines, edges))
    parts, line = shapely.get_parts(shapely.intersection(lines[crossing], edges),
                                    return_index=True)
    line = crossing[line]
    coords, part = shapely.get_coordinates(parts, return_index=True)
    first = np.flatnonzero(np.r_[True, part[1:] != part[:-1]]) if len(part) else part
    reaches = [limit] * len(corners)
    for point, site in zip(coords[first], line[part[first]] // 3):
        reaches[site] = min(reaches[site], float(np.dot(point - corners[site], across[site])))
    return reaches


def _edges_to_stand_on(footprint: Polygon,
                       corridors: Sequence[Polygon]) -> list[tuple[Point2, Point2]]:
    """Edges a core may stand along, each with the free side on its left: the
    footprint's edges (counter-clockwise) and the corridors' edges (clockwise, so the
    left is outside the corridor)."""
    rings = [list(orient(footprint, sign=1.0).exterior.coords)[:-1]]
    rings += [list(orient(c, sign=-1.0).exterior.coords)[:-1] for c in corridors]
    return [(a, b) for ring in rings for a, b in zip(ring, ring[1:] + ring[:1])]


def _free_region(footprint: Polygon, corridors: Sequence[Polygon]) -> Polygon | MultiPolygon:
    """The footprint less its corridors: what the BSP and the core share."""
    return shapely.set_precision(footprint.difference(unary_union(list(corridors))), 1e-6) \
        if corridors else footprint


@dataclass(frozen=True)
class _Room:
    """What every candidate core of one footprint is tested against, computed once per
    :func:`place_core` (the buffered footprint and the free region's own narrow area
    would otherwise be recomputed for each of a few hundred candidates)."""

    outline: Polygon
    free: Polygon | MultiPolygon
    free_parts: int
    free_narrow: float
    min_width: float
    edges: shapely.Geometry

    @classmethod
    def of(cls, footprint: Polygon, free: Polygon | MultiPolygon, min_width: float) -> "_Room":
        edges = free.boundary
        shapely.prepare(edges)
        return cls(outline=footprint.buffer(1e-7), free=free, free_parts=_parts(free),
                   free_narrow=_narrow_area(free, min_width), min_width=min_width,
                   edges=edges)

    def fits(self, rect: Polygon) -> bool:
        """The core lies inside, cuts the free region into no more parts than it had,
        and leaves no part of it narrower than ``min_width`` that was not already."""
        if not self.outline.covers(rect):
            return False
        rest = shapely.set_precision(self.free.difference(rect), 1e-6)
        if rest.is_empty or _parts(rest) > self.free_parts:
            return False
        return _narrow_area(rest, self.min_width) - self.free_narrow < 1e-3


def _parts(region: shapely.Geometry) -> int:
    return len(getattr(region, "geoms", [region]))


def _narrow_area(region: shapely.Geometry, min_width: float) -> float:
    """Area of ``region`` that a disc of diameter ``min_width`` cannot sweep (a
    morphological opening)."""
    r = min_width / 2 - 1e-3
    opened = region.buffer(-r, join_style="mitre").buffer(r, join_style="mitre")
    return region.area - opened.area


def core_for_storey(cache: dict[str, Any], seed: int, footprint: Polygon, storey_height: float,
                    storeys: int, params: StairParams, *, wall: float, door_width: float,
                    min_width: float, corridors: Sequence[Polygon] = ()) -> StairCore:
    """The stair core of the building this storey belongs to.

    Storeys are derived one at a time; the first storey of a building to ask places the
    core and registers it in the build's shared cache under the footprint (rounded to a
    micrometre) and the storey height, so every storey of the stack gets the very same
    rectangle even when their rules give different room counts. The place is drawn from
    the stream ``(seed, "stair_core", footprint)``, which does not depend on which storey
    asks first. ``corridors`` are those of the storey that places the core (usually the
    ground floor): the core keeps clear of them and opens onto one when it can.
    """
    key = f"stair_core:{shapely.set_precision(footprint, 1e-6).wkt}:{storey_height:.6f}"
    core = cache.get(key)
    if core is None:
        rng = stream(seed, ("stair_core", shapely.set_precision(footprint, 1e-6).wkt))
        core = place_core(footprint, storey_height, storeys, params, wall=wall,
                          door_width=door_width, min_width=min_width, rng=rng,
                          corridors=corridors)
        cache[key] = core
    return core
