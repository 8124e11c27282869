"""Facade geometry fitted to the storeys it wraps.

A grammar may split a storey's mass into facade faces (``component_split("side_faces")``,
panes, piers, parapets) and also give the same storey an interior (``make_floor``). The
two are derived independently: the facade knows nothing of rooms, and make_floor places
its windows per room and ``type_rooms`` its doors, long after any facade split. So the
floor plan is the one source of openings, and the facade follows it: every door and
window of a storey's outer walls is cut through the facade geometry in front of it, and
facade geometry reaching into a room is cut back to the room's walls. A facade is then
never an obstacle across a door or inside the building (navigability, physics, and any
simulator the world is exported to), and its openings are the floor's openings.

Why the plan and not the facade split is the source: a facade pane may fall where an
inner wall meets the shell, and doors are chosen by the room typing; a window taken from
a facade split would have to move or vanish anyway, while a plan's openings always fit
its rooms (docs/make_floor.md, "Facades and interiors").

Cutting is exact: a mass (an extruded pane, a parapet) loses the cutters with a
manifold3d difference; a face (an open polygon) loses the cutters' cross-section in its
own plane (:meth:`manifold3d.Manifold.slice`), then is triangulated again, holes and all.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
import trimesh
from shapely.geometry import Polygon

from cga.manifold import manifold3d
from cga.mesh import MeshLike, TriangleMesh, is_watertight
from cga.model import FloorPlan, Opening, Wall
from cga.scene import SceneNode

__all__ = ["FACADE_DEPTH", "StoreyCutter", "fit_facade", "storey_cutters"]

FACADE_DEPTH = 1.0
"""How far (m) in front of an outer wall a door or window is kept clear of facade
geometry: deeper than panes, piers, frames and sills, and beyond where the navigability
check puts the robot outside the front door."""

_CEILING_GAP = 1e-3
"""The room cutters stop this far (m) below the storey's top, so a face lying on the top
of the storey (a roof or the next floor's bottom) is not cut along its own plane."""


@dataclass(frozen=True)
class StoreyCutter:
    """What facade geometry must leave free on one storey: its rooms and, in front of
    each opening of its outer walls, a box ``FACADE_DEPTH`` deep, as one solid."""

    floor: int
    solid: manifold3d.Manifold
    bounds: np.ndarray
    """Axis-aligned bounds of ``solid`` (2×3, world), to skip far-away geometry fast."""


def storey_cutters(plans: Sequence[FloorPlan]) -> list[StoreyCutter]:
    """One cutter per storey (a storey without rooms has none)."""
    out = []
    for plan in plans:
        pieces = [_room_prism(plan)]
        pieces += [_opening_box(wall, opening, plan.floor_y)
                   for wall in plan.walls if wall.outer for opening in wall.openings]
        solid = manifold3d.Manifold.batch_boolean([p for p in pieces if p is not None],
                                                  manifold3d.OpType.Add)
        if solid.is_empty():
            continue
        lo, hi = solid.bounding_box()[:3], solid.bounding_box()[3:]
        out.append(StoreyCutter(plan.index, solid, np.array([lo, hi], dtype=float)))
    return out


def fit_facade(node: SceneNode, cutters: Sequence[StoreyCutter]) -> SceneNode | None:
    """``node`` (a terminal mass or face) less every storey's cutter it meets.

    Returns the node unchanged when it meets none, a node with a new mesh (extra
    ``fitted_to``: the floors it was cut for) when it does, or None when nothing of it
    is left (geometry lying wholly inside rooms or openings)."""
    lo, hi = node.mesh.bounds
    hits = [c for c in cutters if np.all(c.bounds[0] <= hi + 1e-9) and np.all(lo <= c.bounds[1] + 1e-9)]
    if not hits:
        return node
    cutter = manifold3d.Manifold.batch_boolean([c.solid for c in hits], manifold3d.OpType.Add)
    mesh = _cut_face(node, cutter) if node.kind == "face" else _cut_solid(node.mesh, cutter)
    if mesh is None:
        return node
    if len(mesh.faces) == 0:
        return None
    if np.isclose(mesh.area, node.mesh.area, rtol=1e-9, atol=1e-9):
        return node
    extras = {**node.extras, "fitted_to": [c.floor for c in hits]}
    return SceneNode(node.path, node.kind, mesh, extras=extras, static=node.static)


def _room_prism(plan: FloorPlan) -> manifold3d.Manifold | None:
    """The rooms' interiors from the walking surface to just under the storey's top."""
    rooms = shapely.union_all([r.interior for r in plan.rooms])
    height = plan.elevation + plan.height - _CEILING_GAP - plan.floor_y
    if rooms.is_empty or not height > 0:
        return None
    solids = []
    for polygon in getattr(rooms, "geoms", [rooms]):
        if not isinstance(polygon, Polygon) or polygon.is_empty:
            continue
        # cross-section in (x, -z) extruded along +z, turned y-up: (x, -z, h) → (x, h, z)
        rings = [[(x, -z) for x, z in ring.coords[:-1]]
                 for ring in (polygon.exterior, *polygon.interiors)]
        section = manifold3d.CrossSection(rings, manifold3d.FillRule.EvenOdd)
        prism = manifold3d.Manifold.extrude(section, height)
        turn = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, plan.floor_y], [0.0, -1.0, 0.0, 0.0]])
        solids.append(prism.transform(turn))
    return manifold3d.Manifold.batch_boolean(solids, manifold3d.OpType.Add) if solids else None


def _opening_box(wall: Wall, opening: Opening, y0: float) -> manifold3d.Manifold:
    """The opening's box from inside the wall to ``FACADE_DEPTH`` in front of it."""
    t = wall.thickness
    d = np.array([wall.direction[0], 0.0, wall.direction[1]])
    n = np.array([-d[2], 0.0, d[0]])  # into the building: the outside is on an outer wall's right
    start = np.array([wall.start[0], 0.0, wall.start[1]])
    origin = (start + d * (opening.center - opening.width / 2) - n * FACADE_DEPTH
              + np.array([0.0, y0 + opening.sill, 0.0]))
    frame = np.column_stack([d, [0.0, 1.0, 0.0], n, origin])
    return manifold3d.Manifold.cube((opening.width, opening.height, FACADE_DEPTH + 2 * t)).transform(frame)


def _cut_solid(mesh: MeshLike, cutter: manifold3d.Manifold) -> trimesh.Trimesh | None:
    """A watertight mesh less the cutter; None when the mesh is not a solid."""
    if not is_watertight(np.asarray(mesh.faces)):  # see cga.checks._solids.as_manifold
        return None
    solid = manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.asarray(mesh.vertices, dtype=float),
        tri_verts=np.asarray(mesh.faces, dtype=np.uint64)))
    if solid.status() != manifold3d.Error.NoError or solid.is_empty():
        return None
    out = (solid - cutter).to_mesh64()
    return trimesh.Trimesh(vertices=np.asarray(out.vert_properties)[:, :3],
                           faces=np.asarray(out.tri_verts, dtype=np.int64), process=False)


def _cut_face(node: SceneNode, cutter: manifold3d.Manifold
              ) -> "TriangleMesh | trimesh.Trimesh | None":
    """A planar face less the cutter's cross-section in the face's plane."""
    from .shapes import polygon_mesh

    mesh = node.mesh
    normal = np.asarray(mesh.face_normals, dtype=float).sum(axis=0)
    if not np.linalg.norm(normal) > 0:
        return None
    normal /= np.linalg.norm(normal)
    origin = np.asarray(mesh.vertices[0], dtype=float)
    u = np.asarray(mesh.vertices, dtype=float) - origin
    u = u[np.argmax(np.linalg.norm(u - np.outer(u @ normal, normal), axis=1))]
    u = u - normal * (u @ normal)
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    # world → face frame (u, v, normal): the face's plane is z = 0
    rotation = np.vstack([u, v, normal])
    to_local = np.column_stack([rotation, -rotation @ origin])
    section = cutter.transform(to_local).slice(0.0)
    if section.is_empty():
        return mesh
    holes = _section_polygon(section.to_polygons())
    local = np.asarray(mesh.vertices, dtype=float) @ rotation.T - rotation @ origin
    face = shapely.union_all(shapely.polygons(local[np.asarray(mesh.faces)][:, :, :2]).tolist())
    rest = shapely.make_valid(face).difference(holes)
    return polygon_mesh(rest, origin, u, v, normal)


def _section_polygon(rings: Sequence[np.ndarray]) -> shapely.Geometry:
    """A manifold3d cross-section (outer rings counter-clockwise, holes clockwise) as
    one shapely geometry."""
    outer: list[Polygon] = []
    inner: list[Polygon] = []
    for ring in rings:
        if len(ring) >= 3:
            polygon = Polygon(ring)
            side = outer if shapely.is_ccw(polygon.exterior) else inner
            side.append(polygon if polygon.is_valid else shapely.make_valid(polygon))
    return shapely.union_all(outer).difference(shapely.union_all(inner)) if outer else Polygon()
