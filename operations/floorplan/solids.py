"""3D walls and slabs of a floor plan, made at meshing time from the final plan.

``make_floor`` only makes the plan; doors are added later by ``type_rooms``. So the
solids are built last, from whatever openings the walls carry then (DESIGN §6):

* every wall (DCEL edge) becomes one prism from the walking surface up to the top of the
  storey, ``wall_thickness`` thick: inner walls centred on their edge, outer walls inside
  the footprint. Where walls meet, the joint belongs to exactly one of them (outer walls
  first, then the wall running straight through), so wall solids never overlap and
  together fill the footprint minus the rooms' interiors;
* doors and windows are boxes subtracted with manifold3d, so every wall stays a
  watertight solid;
* the floor slab fills the footprint below the walking surface; the top storey also gets
  a roof slab on top of its walls (lower storeys are covered by the next floor's slab).
"""

from __future__ import annotations


import manifold3d
import numpy as np
import shapely
import trimesh
from shapely.geometry import MultiPolygon, Polygon

from cga.model import FloorPlan, Opening, Wall
from cga.scene import SceneNode

__all__ = ["wall_footprints", "floor_nodes"]

_DIGITS = 6  # band corners are rounded to the micrometre, like room interiors, so
# overlays meet exactly instead of leaving float slivers
_SLIVER = 1e-8  # pieces smaller than this (m²) are dropped
_BELOW = 0.01  # doors are cut from a little below the walking surface, cleanly through


def wall_footprints(plan: FloorPlan) -> dict[int, Polygon | MultiPolygon]:
    """Each wall's solid seen from above, in plan ``(x, z)``.

    Parameters
    ----------
    plan
        A floor plan (rooms with interiors, walls with thickness).

    Returns
    -------
    dict
        Wall id → its footprint. The footprints do not overlap; together they cover the
        floor's footprint minus the room interiors. A wall shorter than the joints at its
        ends can be covered entirely by its neighbours and is then missing.

    Notes
    -----
    A wall's band is extended by the wall thickness at an end where no collinear wall
    continues it, clipped to the footprint and cut back by the room interiors it
    reaches; a joint goes to the earlier wall in the order: outer walls, then inner
    walls, each by the decreasing length of the straight run of walls they belong to
    (so a wall running through a T-junction keeps the joint), then by length and id. Vectorised shapely overlays plus a few small
    differences per wall, neighbours found with STRtrees: O(n log n) for n walls.
    """
    t = plan.settings.wall_thickness
    ends: dict[tuple[float, float], list[Wall]] = {}
    for w in plan.walls:
        for p in (w.start, w.end):
            ends.setdefault(_key(p), []).append(w)
    continued = {w.id: [_continuation(w, p, ends) for p in (w.start, w.end)] for w in plan.walls}
    line = _line_lengths(plan.walls, continued)
    walls = sorted(plan.walls, key=lambda w: (not w.outer, -line[w.id], -w.length, w.id))
    bands = np.array([_band(w, t, continued[w.id][0] is None, continued[w.id][1] is None) for w in walls])
    # Clip to the footprint and cut away the (disjoint) room interiors each band reaches.
    interiors = np.array([r.interior for r in plan.rooms])
    band_of, room_of = shapely.STRtree(interiors).query(bands, predicate="intersects")
    reached: list[list[Polygon]] = [[] for _ in walls]
    for b, r in zip(band_of.tolist(), room_of.tolist()):
        reached[b].append(interiors[r])
    clipped = shapely.difference(shapely.intersection(bands, plan.footprint),
                                 [MultiPolygon(parts) for parts in reached])
    # Joints go to the earlier wall: subtract every earlier band that overlaps.
    before, after = shapely.STRtree(clipped).query(clipped, predicate="intersects")
    earlier: list[list[int]] = [[] for _ in walls]
    for i, j in zip(before.tolist(), after.tolist()):
        if j < i:
            earlier[i].append(j)
    out: dict[int, Polygon | MultiPolygon] = {}
    for i, w in enumerate(walls):
        piece = clipped[i]
        for j in earlier[i]:
            piece = piece.difference(clipped[j])
        piece = _without_slivers(shapely.simplify(piece, 0.0))
        if piece is not None:
            out[w.id] = piece
    return out


def floor_nodes(plan: FloorPlan) -> list[SceneNode]:
    """The storey's solids as scene nodes (world coordinates, metres, y up).

    Parameters
    ----------
    plan
        The final plan of one storey (after typing and furniture, so doors are present).

    Returns
    -------
    list[SceneNode]
        One ``"wall"`` node per wall, at ``floor{index}/{room label}/wall{id}`` under the
        wall's lower-id room, with extras ``wall_id``, ``outer``, ``rooms`` (the room ids,
        the outside omitted) and ``openings`` (how many were cut); then
        ``floor{index}/slab`` (``"slab"``) and, when ``plan.is_top``,
        ``floor{index}/ceiling`` (``"ceiling"``). Every mesh is watertight.

    Notes
    -----
    Walls without openings are plain extrusions; a wall with openings is one manifold
    batch subtraction. About 10 ms for a 10-room floor with windows and doors.
    """
    y0 = plan.floor_y
    top = plan.elevation + plan.height
    footprints = wall_footprints(plan)
    labels = {r.id: r.label for r in plan.rooms}
    nodes = []
    for wall in plan.walls:
        piece = footprints.get(wall.id)
        if piece is None:
            continue
        solid = _prism(piece, y0, top)
        if wall.openings:
            cutters = [_opening_box(wall, o, y0) for o in wall.openings]
            solid = manifold3d.Manifold.batch_boolean([solid, *cutters], manifold3d.OpType.Subtract)
        rooms = [r for r in wall.rooms if r >= 0]
        path = f"floor{plan.index}/{labels[min(rooms)]}/wall{wall.id}"
        nodes.append(SceneNode(path, "wall", _mesh(solid), extras={
            "wall_id": wall.id, "outer": wall.outer, "rooms": rooms,
            "openings": len(wall.openings)}))
    slab = plan.settings.slab_thickness
    nodes.append(SceneNode(f"floor{plan.index}/slab", "slab",
                           _mesh(_prism(plan.footprint, plan.elevation, y0)),
                           extras={"floor": plan.index}))
    if plan.is_top:
        nodes.append(SceneNode(f"floor{plan.index}/ceiling", "ceiling",
                               _mesh(_prism(plan.footprint, top, top + slab)),
                               extras={"floor": plan.index}))
    return nodes


def _key(p: tuple[float, float]) -> tuple[float, float]:
    return (round(p[0], 6), round(p[1], 6))


def _continuation(wall: Wall, point: tuple[float, float],
                  ends: dict[tuple[float, float], list[Wall]]) -> Wall | None:
    """The wall that goes on in a straight line from ``wall`` at ``point``, if any."""
    d = wall.direction
    for other in ends[_key(point)]:
        if other is not wall:
            e = other.direction
            if abs(d[0] * e[1] - d[1] * e[0]) < 1e-9:
                return other
    return None


def _line_lengths(walls: tuple[Wall, ...], continued: dict[int, list[Wall | None]]) -> dict[int, float]:
    """Length of the straight run of walls each wall belongs to (walls that continue
    one another in a line, across T-junctions)."""
    out: dict[int, float] = {}
    for w in walls:
        if w.id in out:
            continue
        run, todo = [], [w]
        while todo:
            v = todo.pop()
            if v.id in out:
                continue
            out[v.id] = 0.0
            run.append(v)
            todo.extend(c for c in continued[v.id] if c is not None)
        total = sum(v.length for v in run)
        for v in run:
            out[v.id] = total
    return out


def _band(wall: Wall, t: float, at_start: bool, at_end: bool) -> Polygon:
    """The wall's strip: across ``[-t/2, t/2]`` (inner) or ``[0, t]`` to its left (outer)."""
    d = wall.direction
    n = np.array([-d[1], d[0]])
    a = np.asarray(wall.start) - d * (t if at_start else 0.0)
    b = np.asarray(wall.end) + d * (t if at_end else 0.0)
    lo, hi = (0.0, t) if wall.outer else (-t / 2, t / 2)
    corners = np.round([a + n * lo, b + n * lo, b + n * hi, a + n * hi], _DIGITS)
    return Polygon(corners)


def _without_slivers(geometry) -> Polygon | MultiPolygon | None:
    parts = [p for p in getattr(geometry, "geoms", [geometry]) if isinstance(p, Polygon) and p.area > _SLIVER]
    if not parts:
        return None
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


def _prism(area: Polygon | MultiPolygon, y_low: float, y_high: float) -> manifold3d.Manifold:
    """Vertical prism over a plan area. The cross-section is built in (x, -z) and
    extruded along +z, then turned so that +z becomes +y (a proper rotation)."""
    contours = []
    for polygon in getattr(area, "geoms", [area]):
        for ring in [polygon.exterior, *polygon.interiors]:
            xz = np.asarray(ring.coords)[:-1]
            contours.append(np.column_stack([xz[:, 0], -xz[:, 1]]))
    section = manifold3d.CrossSection(contours, manifold3d.FillRule.EvenOdd)
    turn = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, y_low], [0.0, -1.0, 0.0, 0.0]])
    return manifold3d.Manifold.extrude(section, y_high - y_low).transform(turn)


def _opening_box(wall: Wall, opening: Opening, y0: float) -> manifold3d.Manifold:
    """A box through the wall at the opening: along the wall, up, and across it with
    room to spare on both sides."""
    t = wall.thickness
    d = np.array([wall.direction[0], 0.0, wall.direction[1]])
    n = np.array([-d[2], 0.0, d[0]])
    bottom = y0 + opening.sill if opening.sill > 0 else y0 - _BELOW
    height = y0 + opening.sill + opening.height - bottom
    start = np.array([wall.start[0], 0.0, wall.start[1]])
    origin = start + d * (opening.center - opening.width / 2) - n * 2 * t + np.array([0.0, bottom, 0.0])
    # columns: along (d), up (y), across (n): a right-handed frame, determinant +1
    frame = np.column_stack([d, [0.0, 1.0, 0.0], n, origin])
    return manifold3d.Manifold.cube((opening.width, height, 4 * t)).transform(frame)


def _mesh(solid: manifold3d.Manifold) -> trimesh.Trimesh:
    mesh = solid.to_mesh64()
    vertices = np.asarray(mesh.vert_properties)[:, :3]
    return trimesh.Trimesh(vertices=vertices, faces=np.asarray(mesh.tri_verts), process=False)
