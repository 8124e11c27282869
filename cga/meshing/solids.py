"""3D walls and slabs of a storey, made by the meshing layer from the final plan.

``make_floor`` only makes the plan; doors are added later by ``type_rooms``. So the
solids are built last, from whatever openings the walls carry then (docs/architecture.md,
"Floor plans"):

* every wall (DCEL edge) becomes one prism from the walking surface up to the top of the
  storey, ``wall_thickness`` thick: inner walls centred on their edge, outer walls inside
  the footprint. Where walls meet, the joint belongs to exactly one of them (outer walls
  first, then the wall running straight through), so wall solids never overlap and
  together fill the footprint minus the rooms' interiors;
* doors and windows are boxes subtracted with manifold3d, so every wall stays a
  watertight solid;
* the floor slab fills the footprint below the walking surface, less the stairwell of a
  stair arriving from below (DESIGN §12); the top storey (``is_top``) also gets a roof
  slab, in the top ``slab_thickness`` of the storey, where the next floor's slab would
  be, and its walls stop under it (lower storeys are covered by the next floor's slab),
  so the building stays within the mass it was cut from.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from cga.manifold import manifold3d
from cga.mesh import TriangleMesh, is_watertight
from cga.model import FloorPlan, Opening, Wall
from cga.scene import SceneNode

from .prisms import oriented_rings, prism

__all__ = ["wall_footprints", "floor_nodes"]

_DIGITS = 6  # band corners on the micrometre grid, like room interiors: overlays meet exactly
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
    A wall's band reaches into the joint at an end where no collinear wall continues it:
    an outer wall by ``t`` at an inner corner of the footprint, an inner wall by ``t/2``
    where it meets another inner wall. A joint claimed twice goes to the wall that comes
    first in the order: outer walls, then inner walls, each by the decreasing length of
    the straight run of walls they belong to (so a wall running through a T-junction
    keeps the joint), then by length and id. For axis-aligned walls the bands need no
    further clipping; other bands are clipped to the footprint and cut back by the room
    interiors they overlap. Shapely overlays only where bands overlap, found with
    STRtrees: O(n log n) for n walls.
    """
    t = plan.settings.wall_thickness
    at = _joints(plan.walls)
    continued = {w.id: [_continuation(w, joint) for joint in at[w.id]] for w in plan.walls}
    line = _line_lengths(plan.walls, continued)
    walls = sorted(plan.walls, key=lambda w: (not w.outer, -line[w.id], -w.length, w.id))
    bands = _bands([w.band_corners(*(_reach(w, end, at[w.id][k], t)
                                     if continued[w.id][k] is None else 0.0
                                     for k, end in enumerate(("start", "end"))))
                    for w in walls])
    outside = ~shapely.within(bands, plan.footprint)
    bands[outside] = shapely.intersection(bands[outside], plan.footprint)
    interiors = np.array([r.interior for r in plan.rooms])
    for b, r in zip(*_overlapping(bands, interiors)):
        bands[b] = bands[b].difference(interiors[r])
    # A joint claimed twice goes to the earlier wall.
    earlier: list[list[int]] = [[] for _ in walls]
    for i, j in zip(*_overlapping(bands, bands, earlier=True)):
        earlier[i].append(j)
    pieces = _claimed(bands, earlier)
    out: dict[int, Polygon | MultiPolygon] = {}
    for w, piece in zip(walls, map(_without_slivers, pieces)):
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
        ``floor{index}/slab`` (``"slab"``, with the stairwell cut out; extra
        ``stairwell``: the stair's id or None) and, when ``plan.is_top``,
        ``floor{index}/roof`` (``"roof"``). Every mesh is watertight.

    Notes
    -----
    Walls without openings are plain prisms; a wall with openings is one manifold batch
    subtraction (most of the time goes there). Coordinates stay in double precision
    throughout. About 13 ms of CPU for a 10-room floor with windows and doors.
    """
    y0 = plan.floor_y
    top = plan.elevation + plan.height
    slab = plan.settings.slab_thickness
    if plan.is_top:  # the roof slab takes the top of the storey, as the next floor's would
        top -= slab
    footprints = wall_footprints(plan)
    labels = {r.id: r.label for r in plan.rooms}
    nodes = []
    for wall in plan.walls:
        piece = footprints.get(wall.id)
        if piece is None:
            continue
        vertices, faces = prism(piece, y0, top)
        if wall.openings:
            mesh = _cut(vertices, faces, [_opening_box(wall, o, y0) for o in wall.openings])
        else:
            mesh = _mesh(vertices, faces)
        rooms = [r for r in wall.rooms if r >= 0]
        path = f"floor{plan.index}/{labels[min(rooms)]}/wall{wall.id}"
        nodes.append(SceneNode(path, "wall", mesh, extras={
            "wall_id": wall.id, "outer": wall.outer, "rooms": rooms,
            "openings": len(wall.openings)}))
    well = plan.stairwell
    floor_area = plan.footprint if well is None else plan.footprint.difference(well)
    nodes.append(SceneNode(f"floor{plan.index}/slab", "slab",
                           _slab(floor_area, [r.interior for r in plan.rooms],
                                 plan.elevation, y0),
                           extras={"floor": plan.index,
                                   "stairwell": below.id if (below := plan.stair_down) else None}))
    if plan.is_top:
        nodes.append(SceneNode(f"floor{plan.index}/roof", "roof",
                               _mesh(*prism(plan.footprint, top, top + slab)),
                               extras={"floor": plan.index}))
    return nodes


def _overlapping(geometries: np.ndarray, others: np.ndarray, *,
                 earlier: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The pairs ``(i, j)`` where ``geometries[i]`` overlaps ``others[j]`` (with ``earlier``,
    only those with ``j < i``), in the order ``STRtree(others).query(geometries,
    predicate="overlaps")`` gives them.

    The tree finds the pairs whose bounding boxes meet; most of them only touch (walls
    meet their neighbours and rooms edge to edge), and shapes whose boxes share no
    inner point cannot share one either, so those are dropped before GEOS's overlap test,
    which the query would make on every pair and which costs most of it. Dropping pairs
    keeps the order of the rest. (GEOS agrees wherever its robust arithmetic is exact:
    with subnormal coordinates, never found on the plan's micrometre grid, it can call
    shapes that only touch overlapping.)"""
    i, j = shapely.STRtree(others).query(geometries)
    if earlier:
        keep = j < i
        i, j = i[keep], j[keep]
    a, b = shapely.bounds(geometries)[i], shapely.bounds(others)[j]
    inner = ((np.maximum(a[:, 0], b[:, 0]) < np.minimum(a[:, 2], b[:, 2]))
             & (np.maximum(a[:, 1], b[:, 1]) < np.minimum(a[:, 3], b[:, 3])))
    i, j = i[inner], j[inner]
    keep = shapely.overlaps(geometries[i], others[j])
    return i[keep], j[keep]


def _claimed(bands: np.ndarray, earlier: list[list[int]]) -> np.ndarray:
    """Each band less the ``earlier`` bands that overlap it, one after another, and
    simplified (``shapely.simplify(piece, 0.0)``, dropping the corners left in line)
    where any was cut; the others as they are.

    Every band's first earlier band is cut from it in one shapely call (the same GEOS
    difference, band by band, without shapely's overhead per call), any further one (a
    wall between two earlier ones) after it, one by one."""
    pieces = bands.copy()
    cut = [i for i, e in enumerate(earlier) if e]
    if cut:
        pieces[cut] = shapely.difference(bands[cut], bands[[earlier[i][0] for i in cut]])
        for i in cut:
            for j in earlier[i][1:]:
                pieces[i] = pieces[i].difference(bands[j])
        pieces[cut] = shapely.simplify(pieces[cut], 0.0)
    return pieces


def _key(p: tuple[float, float]) -> tuple[float, float]:
    return (round(p[0], 6), round(p[1], 6))


def _joints(walls: tuple[Wall, ...]) -> dict[int, tuple[list[Wall], list[Wall]]]:
    """For each wall (by id), the walls meeting at its start and at its end (itself
    among them), in wall order: ends are the same joint when their :func:`_key` is.
    Each end's key is worked out once (``round`` costs more than the rest of a wall's
    joint bookkeeping)."""
    joints: dict[tuple[float, float], list[Wall]] = {}
    at = {w.id: (joints.setdefault(_key(w.start), []), joints.setdefault(_key(w.end), []))
          for w in walls}
    for w in walls:
        for joint in at[w.id]:
            joint.append(w)
    return at


def _continuation(wall: Wall, joint: list[Wall]) -> Wall | None:
    """The wall that goes on in a straight line from ``wall`` at one of its ends (the
    walls there: ``joint``) with the same band (both inner or both outer), if any."""
    d = wall.unit()
    for other in joint:
        if other is not wall and other.outer == wall.outer:
            e = other.unit()
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


def _reach(wall: Wall, end: str, joint: list[Wall], t: float) -> float:
    """How far ``wall`` reaches past its ``end`` ("start" or "end") into the joint there
    (the walls meeting there: ``joint``), when no collinear wall continues it."""
    others = [o for o in joint if o is not wall]
    if not wall.outer:
        return 0.0 if any(o.outer for o in others) else t / 2
    # Outer walls run counter-clockwise around the footprint: a right turn at the
    # joint is an inner (reflex) corner, where the joint square lies past the end.
    neighbour = next(o for o in others if o.outer)
    incoming, outgoing = (wall, neighbour) if end == "end" else (neighbour, wall)
    a, b = incoming.unit(), outgoing.unit()
    return t if a[0] * b[1] - a[1] * b[0] < 0 else 0.0


def _bands(corners: list[np.ndarray]) -> np.ndarray:
    """The walls' strips (each :meth:`Wall.band_corners`, reaching into the joints) as
    polygons, their corners on the micrometre grid: one shapely call for all of them,
    as making each polygon on its own cost more than everything else done to it."""
    return shapely.polygons(np.round(np.reshape(corners, (-1, 4, 2)), _DIGITS))


def _without_slivers(geometry) -> Polygon | MultiPolygon | None:
    parts = [p for p in getattr(geometry, "geoms", [geometry]) if isinstance(p, Polygon) and p.area > _SLIVER]
    if not parts:
        return None
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


def _slab(area: Polygon | MultiPolygon, rooms: list[Polygon], y_low: float,
          y_high: float) -> TriangleMesh:
    """The floor slab: the prism over ``area`` whose walking surface is triangulated room
    by room (each room's floor, then the rest: the walls' footprint), so every top
    triangle lies in one room and the appearance can give each room its own floor
    (docs/appearance.md). Shared corners are one vertex, so the slab stays watertight; if
    a room's outline would break that (a corner on the slab's edge), the top is one
    triangulation, as for any prism."""
    vertices, faces = prism(area, y_low, y_high)
    pieces = [area.intersection(room) for room in rooms]
    pieces = [p for p in pieces if not p.is_empty and p.area > _SLIVER]
    rest = area.difference(shapely.union_all(pieces)) if pieces else area
    rings = []
    for piece in [*pieces, rest]:
        for polygon in getattr(piece, "geoms", [piece]):
            if isinstance(polygon, Polygon) and polygon.area > _SLIVER:
                rings.append(oriented_rings(polygon))
    n = len(vertices) // 2
    index = {_key(p): k for k, p in enumerate(vertices[n:, [0, 2]].tolist(), start=n)}
    extra: list[tuple[float, float, float]] = []
    top = []
    for polygon_rings in rings:
        ids = []
        for x, z in np.concatenate(polygon_rings).tolist():  # floats: no numpy per corner
            key = _key((x, z))
            if key not in index:
                index[key] = len(vertices) + len(extra)
                extra.append((x, y_high, z))
            ids.append(index[key])
        triangles = np.asarray(manifold3d.triangulate(polygon_rings), dtype=np.int64)
        top.append(np.array(ids, dtype=np.int64)[triangles.reshape(-1, 3)[:, ::-1]])
    caps = _cap_count(faces, n)
    candidate = np.vstack([faces[:caps], faces[2 * caps:], *top])
    if is_watertight(candidate):
        return _mesh(np.concatenate([vertices, np.array(extra)]) if extra else vertices,
                     candidate)
    return _mesh(vertices, faces)


def _cap_count(faces: np.ndarray, n: int) -> int:
    """How many triangles one cap of a :func:`~.prisms.prism` has (the bottom cap comes first,
    then the top cap, then the sides)."""
    return int(np.count_nonzero((faces < n).all(axis=1)))


def _mesh(vertices: np.ndarray, faces: np.ndarray) -> TriangleMesh:
    return TriangleMesh(vertices, faces)


def _opening_box(wall: Wall, opening: Opening, y0: float) -> manifold3d.Manifold:
    """A box through the wall at the opening: along the wall, up, and across it with
    room to spare on both sides.

    The frame is worked out on plain floats (numpy's overhead on 3-vectors outweighs
    the arithmetic), each coordinate by the operations, in the order, of the vector
    formula ``start + d (center - width / 2) - n 2 t + (0, bottom, 0)``, so the floats
    are those of the vector formula."""
    t = wall.thickness
    dx, dz = wall.unit()
    nx, nz = -dz, dx  # d = (dx, 0, dz), n = (-dz, 0, dx): the horizontal normal
    bottom = y0 + opening.sill if opening.sill > 0 else y0 - _BELOW
    height = y0 + opening.sill + opening.height - bottom
    along = opening.center - opening.width / 2
    origin = [wall.start[0] + dx * along - nx * 2 * t + 0.0,
              0.0 + bottom,  # the formula's zeros (+0 whatever their signs), then bottom
              wall.start[1] + dz * along - nz * 2 * t + 0.0]
    # columns: along (d), up (y), across (n): a right-handed frame, determinant +1
    frame = np.array([[dx, 0.0, nx, origin[0]], [0.0, 1.0, 0.0, origin[1]],
                      [dz, 0.0, nz, origin[2]]])
    return manifold3d.Manifold.cube((opening.width, height, 4 * t)).transform(frame)


def _cut(vertices: np.ndarray, faces: np.ndarray, cutters: list[manifold3d.Manifold]) -> TriangleMesh:
    """The solid minus the cutters, by one manifold batch subtraction."""
    solid = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=vertices,
                                                  tri_verts=faces.astype(np.uint64)))
    result = manifold3d.Manifold.batch_boolean([solid, *cutters], manifold3d.OpType.Subtract).to_mesh64()
    return _mesh(np.asarray(result.vert_properties)[:, :3], np.asarray(result.tri_verts))
