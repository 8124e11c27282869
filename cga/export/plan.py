"""Floor plans, ``<name>.floor{N}.svg`` and ``.png``: an architect's sketch of each storey.

What is drawn (docs/outputs.md), bottom to top:

* rooms filled with a soft colour per type (:mod:`cga.export.palette`);
* furniture footprints with outlines and small names (rugs dashed; detail items such
  as door leaves are left to the door symbols);
* stairs: treads, cut line and the "up" walking line on the floor a stair leaves, the
  stairwell opening on the floor it reaches (:mod:`cga.export.plan_stairs`);
* walls as solid dark poured walls of their true thickness: the footprint minus the
  rooms' free floor, with the openings cut out;
* windows as thin double lines in their wall gap; doors as gaps with the leaf drawn
  where the build leaves it (closed across the gap, ajar, open) and a dashed swing arc
  into the swing room; the front door marked outside;
* room labels (type, area in m²) at the most open point of the room's free floor;
* a title with the floor number, a north arrow, a 1 m / 5 m scale bar and a legend of
  the room types on the floor.

Paper frame: world ``x`` to the right, world ``z`` down the page, so north (ROS ``+y``,
world ``−z``) is up, as in the ROS occupancy maps. One :class:`~cga.export.drawing.Drawing`
feeds both the SVG and the PNG.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Point as ShapelyPoint, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import polylabel, unary_union

from cga.fsutil import atomic_write
from cga.model import OUTSIDE, Door, FloorPlan, FurnitureItem, Room, Wall
from cga.scene import Scene, SceneNode

from .drawing import (Arc, Area, Canvas, Drawing, Point, Polyline, Style, Text, render_png,
                      render_svg, text_width)
from .palette import hex_color, room_color
from .plan_stairs import draw_stairs

__all__ = ["MAX_PLAN_PX", "plan_drawing", "export_plans"]

_TARGET_PLAN_PX = 860.0
_MIN_PX_PER_M, _MAX_PX_PER_M = 28.0, 80.0

MAX_PLAN_PX = 2_400.0
"""Longest side of the drawn footprint in pixels (docs/limits.md). Plans are drawn at
28 px/m or more; a footprint longer than about 86 m is drawn smaller instead, so a
300 m lot does not need a raster of gigabytes."""
_MARGIN = 48.0
_HEADER = 64.0
_FOOTER = 56.0
_COLUMN_WIDTH = 200.0

_INK = "#2f2b27"
_WALL = Style(fill="#35312d")
_FURNITURE = Style(fill="#ffffff", stroke="#6f655a", width=1.0, opacity=0.72)
_RUG = Style(stroke="#9c9184", width=0.9, dash=(4.0, 3.0))
_WINDOW_GAP = Style(fill="#ffffff", stroke=_INK, width=0.8)
_GLASS = Style(stroke="#4f86b0", width=1.0)
_LEAF = Style(stroke=_INK, width=1.8)
_HATCHING = Style(stroke="#b9ae9f", width=0.8)
_HATCH_SPACING = 0.35  # m between hatch lines
_HATCH_MIN_PX = 6.0  # and at least this many pixels
_SWING = Style(stroke="#7d7369", width=0.9, dash=(3.0, 2.5))
_ENTRANCE = Style(fill="#c0392b")
_ENTRANCE_TEXT = "entrance"
_ENTRANCE_SIZE = 10.0


@dataclass(frozen=True)
class _Paper:
    """Maps plan ``(x, z)`` metres to paper pixels (x right, z down)."""

    min_x: float
    min_z: float
    scale: float
    left: float
    top: float

    def point(self, x: float, z: float) -> Point:
        return (self.left + (x - self.min_x) * self.scale, self.top + (z - self.min_z) * self.scale)

    def ring(self, coords: Sequence[Sequence[float]]) -> tuple[Point, ...]:
        return tuple(self.point(c[0], c[1]) for c in coords)

    def points(self, coords: np.ndarray) -> list[Point]:
        """The points of an ``n × 2`` array: :meth:`point`'s sums, element by element
        (the same floats), without a call per point."""
        xs = self.left + (coords[:, 0] - self.min_x) * self.scale
        zs = self.top + (coords[:, 1] - self.min_z) * self.scale
        return list(zip(xs.tolist(), zs.tolist()))

    def lines(self, geometries: Sequence[BaseGeometry]) -> list[tuple[Point, ...]]:
        """The points of each linestring or ring in ``geometries``, read in one pass."""
        points = self.points(shapely.get_coordinates(geometries))
        ends = np.cumsum(shapely.get_num_coordinates(geometries)).tolist()
        return [tuple(points[start:end]) for start, end in zip([0, *ends], ends)]

    def areas(self, geometry: BaseGeometry) -> list[tuple[tuple[Point, ...], ...]]:
        """The rings of each polygon of ``geometry``, outline first, without the
        closing repeat of the first point."""
        polygons = (geometry.geoms if isinstance(geometry, MultiPolygon)
                    else [geometry] if isinstance(geometry, Polygon) else [])
        return [tuple(ring[:-1] for ring in self.lines([p.exterior, *p.interiors]))
                for p in polygons if not p.is_empty]


def plan_drawing(plan: FloorPlan, *, title: str, subtitle: str = "") -> Drawing:
    """Compose the plan of one floor.

    Parameters
    ----------
    plan:
        The floor to draw.
    title, subtitle:
        Heading lines printed above the plan.

    Returns
    -------
    Drawing
        Page in pixels; layers ``rooms``, ``furniture``, ``stairs``, ``walls``, ``windows``,
        ``doors``, ``labels``, ``furniture-labels``, ``annotation``. Every room gets
        exactly one ``room-label`` text.
    """
    min_x, min_z, max_x, max_z = plan.footprint.bounds
    extent = max(max_x - min_x, max_z - min_z, 1e-9)
    scale = min(_MAX_PX_PER_M, max(_MIN_PX_PER_M, _TARGET_PLAN_PX / extent),
                MAX_PLAN_PX / extent)
    entrances = [_entrance_marker(door, plan, scale) for door in plan.doors if door.is_front]
    if entrances:  # make room for the markers outside the walls
        min_x, min_z, max_x, max_z = unary_union(
            [plan.footprint, *(part for e in entrances for part in (e.arrow, e.label_box))]).bounds
    paper = _Paper(min_x, min_z, scale, _MARGIN, _HEADER + _MARGIN * 0.5)
    plan_w, plan_h = (max_x - min_x) * scale, (max_z - min_z) * scale
    column_x = _MARGIN + plan_w + _MARGIN
    legend_rows = len(_legend_types(plan))
    height = max(paper.top + plan_h + _FOOTER + 30, paper.top + 120 + 22 * legend_rows)
    drawing = Drawing(width=math.ceil(column_x + _COLUMN_WIDTH), height=math.ceil(height),
                      title=title, background="#fcfbf8")
    footprints = [(item, item.footprint()) for item in plan.furniture if not item.is_detail]
    _draw_rooms(drawing, paper, plan)
    _draw_furniture(drawing, paper, footprints)
    draw_stairs(drawing, plan, paper.point)
    _draw_walls(drawing, paper, plan)
    _draw_windows(drawing, paper, plan)
    _draw_doors(drawing, paper, plan)
    for entrance in entrances:  # one per front door: wings may have their own
        _draw_entrance(drawing, paper, entrance)
    _draw_room_labels(drawing, paper, plan, [footprint for _, footprint in footprints])
    drawing.add("annotation", Text((_MARGIN, 36.0), title, 20, _INK, "start", bold=True,
                                   css_class="title"))
    if subtitle:
        drawing.add("annotation", Text((_MARGIN, 58.0), subtitle, 12, "#6b645c", "start",
                                       css_class="subtitle"))
    _draw_north_arrow(drawing, (column_x + 22, paper.top + 24))
    _draw_legend(drawing, plan, (column_x, paper.top + 84))
    _draw_scale_bar(drawing, paper.scale, (_MARGIN, paper.top + plan_h + 36))
    return drawing


def export_plans(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path,
                 name: str) -> list[Path]:
    """Write ``<name>.floor{N}.svg`` and ``<name>.floor{N}.png`` for every floor."""
    written = []
    canvas = Canvas()
    for plan in scene.floors:
        storey = "ground floor" if plan.index == 0 else f"floor {plan.index}"
        typed = sum(1 for r in plan.rooms if r.type)
        area = sum(r.area for r in plan.rooms)
        share = sum(r.area for r in plan.rooms if r.circulation) / area if area else 0.0
        subtitle = (f"{len(plan.rooms)} rooms ({typed} typed) · {plan.footprint.area:.1f} m² "
                    f"footprint · circulation {100 * share:.0f} % · {len(plan.doors)} doors · "
                    f"{len(plan.windows)} windows · seed {scene.seed}")
        drawing = plan_drawing(plan, title=f"{name} — {storey}", subtitle=subtitle)
        stem = f"{name}.floor{plan.index}"
        written.append(atomic_write(Path(out_dir) / f"{stem}.svg", render_svg(drawing)))
        written.append(atomic_write(Path(out_dir) / f"{stem}.png", render_png(drawing, canvas=canvas)))
    return written


# -- rooms and furniture ----------------------------------------------------------------

def _room_name(room: Room) -> str:
    return room.type if room.type else f"Room {room.id}"


def _draw_rooms(drawing: Drawing, paper: _Paper, plan: FloorPlan) -> None:
    for room in plan.rooms:
        style = Style(fill=hex_color(room_color(room.type)))
        for rings in paper.areas(room.polygon):
            drawing.add("rooms", Area(rings, style, css_class="room"))
        if room.circulation:
            _hatch(drawing, paper, room.interior)


def _hatch(drawing: Drawing, paper: _Paper, region: Polygon, layer: str = "rooms") -> None:
    """Diagonal hatching over circulation (halls, corridors), as plans mark it."""
    min_x, min_z, max_x, max_z = region.bounds
    spacing = max(_HATCH_SPACING, _HATCH_MIN_PX / paper.scale)  # small plans: fewer lines
    span = (max_x - min_x) + (max_z - min_z)
    count = int(span / spacing) + 1
    offsets = (min_x + min_z + k * spacing for k in range(count + 1))  # lines x + z = c
    lines = shapely.linestrings([[(c - min_z + 1, min_z - 1), (c - max_z - 1, max_z + 1)]
                                 for c in offsets])
    parts = shapely.get_parts(shapely.intersection(lines, region))  # all lines in one call
    parts = parts[(shapely.get_type_id(parts) == shapely.GeometryType.LINESTRING)
                  & ~shapely.is_empty(parts)]  # not the points where a line grazes a corner
    for points in paper.lines(parts):
        drawing.add(layer, Polyline(points, _HATCHING, css_class="circulation"))


def _item_label(item: FurnitureItem) -> str:
    """'chair1' → 'chair', 'desk#3' → 'desk', 'SofaTable' → 'sofa table', 'tableBig' →
    'table big'."""
    base = re.sub(r"#?\d+$", "", item.name).strip() or item.model
    return re.sub(r"(?<=[a-z])(?=[A-Z])", " ", base).replace("_", " ").lower()


def _draw_furniture(drawing: Drawing, paper: _Paper,
                    footprints: Sequence[tuple[FurnitureItem, Polygon]]) -> None:
    """The items with their footprints (detail items such as door leaves left out);
    outlines, boxes and centres of all footprints read in one pass each."""
    shapes = [footprint for _, footprint in footprints]
    rings = paper.lines(shapely.get_exterior_ring(shapes))
    boxes = shapely.bounds(shapes).tolist()
    centres = paper.points(shapely.get_coordinates(shapely.centroid(shapes)))
    for (item, _), ring, box, centre in zip(footprints, rings, boxes, centres):
        if item.non_collision:
            drawing.add("furniture", Polyline(ring[:-1], _RUG, closed=True,
                                              css_class="furniture rug"))
        else:
            drawing.add("furniture", Area((ring[:-1],), _FURNITURE, css_class="furniture"))
        _draw_item_name(drawing, paper, item, box, centre)


def _draw_item_name(drawing: Drawing, paper: _Paper, item: FurnitureItem,
                    bounds: Sequence[float], centre: Point) -> None:
    """The item's name at ``centre`` (paper) of its footprint, turned to read along a
    footprint (plan ``bounds``) too narrow for it across."""
    label = _item_label(item)
    min_x, min_z, max_x, max_z = bounds
    across, along = (max_x - min_x) * paper.scale - 4, (max_z - min_z) * paper.scale - 4
    size = 8.5
    for candidate in (8.5, 7.5, 6.5):
        size = candidate
        if text_width(label, size) <= max(across, along):
            break
    vertical = text_width(label, size) > across and along > across and not item.non_collision
    cx, cy = centre
    angle: Literal[0, 90]
    if item.non_collision:  # rugs: name along the bottom edge, clear of what stands on them
        position, angle = (cx, paper.point(min_x, max_z)[1] - 3), 0
    elif vertical:
        position, angle = (cx + size * 0.35, cy), 90
    else:
        position, angle = (cx, cy + size * 0.35), 0
    drawing.add("furniture-labels", Text(position, label, size, "#5d544a", angle=angle,
                                         css_class="furniture-label"))


def _erode(region: BaseGeometry, half_w: float, half_h: float) -> BaseGeometry:
    """Where the centre of a ``2·half_w`` × ``2·half_h`` axis-aligned box can go so that
    the box stays inside ``region`` (erosion by a rectangle: squash x until the box is
    a square, erode with a mitred buffer, stretch back). Vertices a round-off apart
    (a room cut at 13.8 meeting a wall at 13.799999999999999) are merged first: GEOS
    divides by their zero-length edge when it mitres a corner there."""
    k = half_h / half_w
    squashed = _scale_x(region.simplify(1e-9), k)
    eroded = squashed.buffer(-half_h, join_style="mitre")
    return _scale_x(eroded, 1 / k)


def _scale_x(geometry: BaseGeometry, factor: float) -> BaseGeometry:
    """``geometry`` with every x multiplied by ``factor``: the coordinates
    ``affinity.scale(geometry, factor, 1.0, origin=(0, 0))`` gives, which computes
    ``factor·x + 0·z + 0`` and ``0·x + 1·z + 0`` (the zeros added change no value but
    turn −0.0 into 0.0, kept here by ``+ 0.0``), without setting up its matrix."""
    return shapely.transform(geometry, lambda xz: xz * (factor, 1.0) + 0.0)


def _open_point(region: BaseGeometry) -> tuple[float, float]:
    """The most open point of ``region`` (pole of inaccessibility of its roomiest
    piece), moved to the middle of the ridge of nearly as open points so labels in
    rectangular rooms sit centred."""
    pieces = region.geoms if isinstance(region, MultiPolygon) else [region]
    best: tuple[float, ShapelyPoint, Polygon] | None = None
    for piece in pieces:
        if piece.is_empty or piece.area <= 0:
            continue
        centre = polylabel(piece, tolerance=0.01)
        clearance = piece.boundary.distance(centre)
        if best is None or clearance > best[0]:
            best = (clearance, centre, piece)
    if best is None:
        point = region.representative_point() if not region.is_empty else ShapelyPoint(0, 0)
        return (point.x, point.y)
    clearance, centre, piece = best
    ridge = piece.buffer(-0.8 * clearance)
    if not ridge.is_empty and ridge.contains(ridge.centroid):
        centre = ridge.centroid
    return (centre.x, centre.y)


def _obstacles(plan: FloorPlan, furniture: Sequence[Polygon]) -> BaseGeometry:
    """What room labels keep clear of, 5 cm apart: the ``furniture`` footprints, the
    door swings and the stairs (the core's label goes on the landing). Buffered in one
    vectorised call, each shape as its own ``buffer`` would give it (whose default is
    16 segments a quarter circle), and merged in that order."""
    shapes = [*furniture, *(ShapelyPoint(*door.position) for door in plan.doors),
              *(stair.polygon for stair in plan.stairs)]
    margins = ([0.05] * len(furniture) + [door.width + 0.05 for door in plan.doors]
               + [0.05] * len(plan.stairs))
    return shapely.union_all(shapely.buffer(shapes, margins, quad_segs=16))


def _draw_room_labels(drawing: Drawing, paper: _Paper, plan: FloorPlan,
                      furniture: Sequence[Polygon]) -> None:
    """Type and area of every room, placed where the label box fits on free floor
    (clear of the ``furniture`` footprints, door swings and stairs if possible),
    shrinking the font if needed."""
    obstacles = _obstacles(plan, furniture)
    for room in plan.rooms:
        interior = room.interior if not room.interior.is_empty else room.polygon
        name, area = _room_name(room), f"{room.area:.1f} m²"
        regions = (interior.difference(obstacles), interior)
        size, point = 13.0, None
        for region, size in ((r, s) for r in regions for s in (13.0, 11.5, 10.0, 9.0)):
            half_w = (max(text_width(name, size, bold=True),
                          text_width(area, size * 0.82)) / 2 + 3) / paper.scale
            half_h = (1.1 * size + 2) / paper.scale
            fit = _erode(region, half_w, half_h)
            if not fit.is_empty:
                point = _open_point(fit)
                break
        if point is None:
            point = _open_point(interior)
        cx, cy = paper.point(*point)
        drawing.add("labels", Text((cx, cy - 0.05 * size), name, size, "#2b2823", bold=True,
                                   css_class="room-label"))
        drawing.add("labels", Text((cx, cy + 0.95 * size), area, size * 0.82, "#5b554d",
                                   css_class="room-area"))


# -- walls and openings -----------------------------------------------------------------

def _along(wall: Wall, point: Sequence[float]) -> float:
    return float(np.dot(np.subtract(point, wall.start), wall.direction))


def _corners(wall: Wall, s0: float, s1: float, lo: float, hi: float) -> list[tuple[float, float]]:
    """The corners of the part of the wall between ``s0`` and ``s1`` metres along it and
    offsets ``lo`` and ``hi`` across it (along :attr:`Wall.normal`), in that order:
    ``(s0, lo)``, ``(s1, lo)``, ``(s1, hi)``, ``(s0, hi)``. Plain floats: the sums
    numpy would form element by element, in the same order, without its per-call cost."""
    (sx, sz), (ux, uz) = wall.start, wall.unit()
    nx, nz = -uz, ux  # Wall.normal
    return [(sx + ux * s + nx * o, sz + uz * s + nz * o)
            for s, o in ((s0, lo), (s1, lo), (s1, hi), (s0, hi))]


def _draw_walls(drawing: Drawing, paper: _Paper, plan: FloorPlan) -> None:
    interiors = unary_union([r.interior for r in plan.rooms])
    solid = plan.footprint.difference(interiors)
    cuts = []  # the openings' parts of their walls (:func:`_corners`)
    for wall in plan.walls:
        lo, hi = wall.band()
        for opening in wall.openings:
            half = opening.width / 2
            cuts.append(_corners(wall, opening.center - half, opening.center + half,
                                 lo - 0.02, hi + 0.02))
    if cuts:  # built and merged in one call each
        solid = solid.difference(shapely.union_all(shapely.polygons(cuts)))
    for rings in paper.areas(solid):
        drawing.add("walls", Area(rings, _WALL, css_class="wall"))


def _draw_windows(drawing: Drawing, paper: _Paper, plan: FloorPlan) -> None:
    for window in plan.windows:
        wall = plan.wall(window.wall)
        lo, hi = wall.band()
        s = _along(wall, window.position)
        s0, s1 = s - window.width / 2, s + window.width / 2
        gap = _corners(wall, s0, s1, lo, hi)
        drawing.add("windows", Area((paper.ring(gap),), _WINDOW_GAP, css_class="window"))
        for fraction in (0.38, 0.62):
            o = lo + (hi - lo) * fraction
            line = _corners(wall, s0, s1, o, o)[:2]
            drawing.add("windows", Polyline(paper.ring(line), _GLASS, css_class="window-glass"))


def _draw_doors(drawing: Drawing, paper: _Paper, plan: FloorPlan) -> None:
    for door in plan.doors:
        if not door.leaf:  # a bare opening: the gap in the wall is all there is
            continue
        wall = plan.wall(door.wall)
        s = _along(wall, door.position)
        hinge_s, free_s = ((s - door.width / 2, s + door.width / 2) if door.hinge == "start"
                           else (s + door.width / 2, s - door.width / 2))
        # the leaf lies on the face of the wall on the side it swings to
        start, u = np.asarray(wall.start), wall.direction
        n, face = wall.normal_into(door.swing_room), wall.face_offset(door.swing_room)
        hinge = start + u * hinge_s + n * face
        closed = start + u * free_s + n * face
        tip = hinge + n * door.width
        # the leaf where the build leaves it (closed, ajar or open), the arc its full swing
        latch = (closed - hinge) / door.width
        leaf = hinge + (latch * math.cos(door.angle) + n * math.sin(door.angle)) * door.width
        h, t, c = paper.point(*hinge), paper.point(*tip), paper.point(*closed)
        drawing.add("doors", Polyline((h, paper.point(*leaf)), _LEAF, css_class="door-leaf"))
        a0 = math.atan2(t[1] - h[1], t[0] - h[0])
        a1 = math.atan2(c[1] - h[1], c[0] - h[0])
        a1 = a0 + (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
        drawing.add("doors", Arc(h, door.width * paper.scale, a0, a1, _SWING,
                                 css_class="door-swing"))


@dataclass(frozen=True)
class _Entrance:
    """The front-door marker in plan metres: an arrowhead outside the door pointing in,
    and its label: baseline anchor point, text anchor and the box the text covers."""

    arrow: Polygon
    label_at: tuple[float, float]
    anchor: Literal["start", "middle", "end"]
    label_box: Polygon


def _entrance_marker(door: Door, plan: FloorPlan, scale: float) -> _Entrance:
    wall = plan.wall(door.wall)
    u = wall.direction
    position = np.asarray(door.position)
    outward = wall.normal_into(OUTSIDE)
    apex, base = position + outward * 0.25, position + outward * 0.75
    arrow = Polygon([apex, base + u * 0.3, base - u * 0.3])
    width = text_width(_ENTRANCE_TEXT, _ENTRANCE_SIZE, bold=True) / scale
    height = _ENTRANCE_SIZE / scale
    anchor: Literal["start", "middle", "end"]
    if abs(outward[1]) > 0.5:  # north or south wall: centred beyond the arrowhead
        x, z = position + outward * 0.9
        if outward[1] > 0:
            z += height
        anchor, left = "middle", x - width / 2
    else:  # east or west wall: beside the arrowhead, reading away from the wall
        x, z = position + outward * 0.85
        z += height / 2
        if outward[0] > 0:
            anchor, left = "start", x
        else:
            anchor, left = "end", x - width
    box = Polygon.from_bounds(left, z - height, left + width, z + 0.2 * height)
    return _Entrance(arrow, (float(x), float(z)), anchor, box)


def _draw_entrance(drawing: Drawing, paper: _Paper, entrance: _Entrance) -> None:
    drawing.add("doors", Area((paper.ring(entrance.arrow.exterior.coords[:-1]),), _ENTRANCE,
                              css_class="front-door"))
    drawing.add("doors", Text(paper.point(*entrance.label_at), _ENTRANCE_TEXT, _ENTRANCE_SIZE,
                              "#c0392b", entrance.anchor, bold=True,
                              css_class="front-door-label"))


# -- annotation -------------------------------------------------------------------------

def _draw_scale_bar(drawing: Drawing, scale: float, origin: Point) -> None:
    """A 5 m bar in alternating 1 m blocks, labelled at 0 and 5 m (``scale`` px per m)."""
    metres = 5
    x0, y0 = origin
    height = 6.0
    for k in range(metres):
        left = x0 + k * scale
        block = ((left, y0), (left + scale, y0), (left + scale, y0 + height),
                 (left, y0 + height))
        style = Style(fill=_INK if k % 2 == 0 else "#ffffff", stroke=_INK, width=0.8)
        drawing.add("annotation", Area((block,), style, css_class="scale-bar"))
    for k in range(0, metres + 1, 5):
        drawing.add("annotation", Text((x0 + k * scale, y0 + height + 13), str(k), 10,
                                       _INK, css_class="scale-label"))
    drawing.add("annotation", Text((x0 + metres * scale + 8, y0 + height), "m", 10,
                                   _INK, "start", css_class="scale-label"))
    drawing.add("annotation", Text((x0, y0 - 6), "1 m blocks", 9, "#6b645c", "start",
                                   css_class="scale-label"))


def _draw_north_arrow(drawing: Drawing, centre: Point) -> None:
    """An arrow pointing up the page (north = world −z = ROS +y)."""
    x, y = centre
    r = 17.0
    ring = Style(stroke=_INK, width=1.0)
    drawing.add("annotation", Arc((x, y), r, 0.0, math.pi * 0.999, ring))
    drawing.add("annotation", Arc((x, y), r, math.pi, math.pi * 1.999, ring))
    drawing.add("annotation", Area((((x, y - r + 2), (x + 7, y + r - 6), (x, y + r - 11),
                                     (x - 7, y + r - 6)),), Style(fill=_INK), css_class="north"))
    drawing.add("annotation", Text((x, y - r - 5), "N", 12, _INK, bold=True, css_class="north"))


def _legend_types(plan: FloorPlan) -> list[str | None]:
    seen: dict[str | None, None] = {}
    for room in sorted(plan.rooms, key=lambda r: ((r.type or "~").lower(), r.id)):
        seen.setdefault(room.type, None)
    return list(seen)


def _draw_legend(drawing: Drawing, plan: FloorPlan, origin: Point) -> None:
    x, y = origin
    drawing.add("annotation", Text((x, y), "Rooms", 12, _INK, "start", bold=True,
                                   css_class="legend"))
    for row, room_type in enumerate(_legend_types(plan)):
        top = y + 12 + row * 22
        swatch = ((x, top), (x + 16, top), (x + 16, top + 14), (x, top + 14))
        drawing.add("annotation", Area((swatch,), Style(fill=hex_color(room_color(room_type)),
                                                        stroke="#8a8278", width=0.7),
                                       css_class="legend"))
        count = sum(1 for r in plan.rooms if r.type == room_type)
        text = (room_type or "untyped") + (f" ×{count}" if count > 1 else "")
        if any(r.circulation for r in plan.rooms if r.type == room_type):
            _hatch(drawing, _Paper(0.0, 0.0, 10.0, x, top), Polygon(
                [(0, 0), (1.6, 0), (1.6, 1.4), (0, 1.4)]), "annotation")  # hatched as in the plan
        drawing.add("annotation", Text((x + 24, top + 11), text, 11, _INK, "start",
                                       css_class="legend"))
