"""The stair's solids: watertight flights and landings, and the stairwell's guard rail.

* A flight is its side profile, a saw-tooth of risers and treads above a soffit parallel
  to the pitch line (``waist`` below the nosings' line, never below the flight's base),
  extruded across its width: one watertight prism (Ching, *Building Construction
  Illustrated*, stairs: waist-slab stairs). A half landing is a slab ``thickness`` deep
  under its walking surface. Flights and landings are united with manifold3d into one
  watertight solid per stair, ``floor{lower}/stair{id}`` (kind ``"stair"``).
* The stairwell in the upper floor's slab gets a guard rail along its edges open to the
  floor wherever no flight arrives or leaves (the other edges meet the core's walls):
  ``floor{upper}/stairwell{id}/rail`` (kind ``"rail"``), 1.0 m high (EN 1991 / IBC
  guards: at least 0.9–1.07 m).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from cga.manifold import manifold3d
from cga.mesh import TriangleMesh, mirrors, transform_points
from cga.model import Flight, FloorPlan, Stair
from cga.scene import SceneNode

from .prisms import prism, prism_mesh

__all__ = ["RAIL_HEIGHT", "RAIL_THICKNESS", "flight_mesh", "stair_mesh", "rail_footprint",
           "stair_nodes"]

RAIL_HEIGHT = 1.0
"""Height of the guard rail above the walking surface (m)."""

RAIL_THICKNESS = 0.05
"""Thickness of the guard rail (m)."""

_WAIST = 0.12  # m of solid under the line through the treads' inner corners


def _profile(flight: Flight) -> Polygon:
    """The flight's side profile in ``(along, up)``, ``up`` from its base."""
    r, g, m = flight.rise, flight.going, flight.risers
    points = [(0.0, 0.0)]
    for k in range(m - 1):
        points += [(k * g, (k + 1) * r), ((k + 1) * g, (k + 1) * r)]
    points.append(((m - 1) * g, m * r))
    # soffit: through the treads' inner corners lowered by the waist, clipped at the base
    slope = r / g
    end = (m - 1) * g
    low = m * r - r - _WAIST
    start = end - max(low, 0.0) / slope
    points.append((end, max(low, 0.0)))
    if start > 1e-9:
        points.append((start, 0.0))
    return shapely.Polygon(points)


def flight_mesh(flight: Flight) -> TriangleMesh:
    """The flight as a watertight prism in world coordinates (y up): its side profile
    (:func:`_profile`, in ``(along, up)``) extruded across its width."""
    # the prism's plan (x, z) is the profile's (along, up) and its height the width
    vertices, faces = prism(_profile(flight), 0.0, flight.width)
    dx, dz = flight.direction
    along = np.array([dx, 0.0, dz])
    up = np.array([0.0, 1.0, 0.0])
    across = np.array([-dz, 0.0, dx])
    origin = (np.array([flight.start[0], flight.base_y, flight.start[1]])
              - across * flight.width / 2)
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = along, across, up, origin
    if mirrors(matrix):  # a mirroring frame turns the faces inside out
        faces = faces[:, ::-1]
    return TriangleMesh(transform_points(vertices, matrix), faces)


def _manifold(mesh: TriangleMesh) -> manifold3d.Manifold:
    return manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.asarray(mesh.vertices, dtype=np.float64),
        tri_verts=np.asarray(mesh.faces, dtype=np.uint64)))


def stair_mesh(stair: Stair) -> TriangleMesh:
    """The stair's flights and half landing united into one watertight solid."""
    pieces = [flight_mesh(f) for f in stair.flights]
    if stair.half_landing is not None:
        top = stair.flights[0].top_y
        pieces.append(prism_mesh(stair.half_landing, top - stair.thickness, top))
    solid = manifold3d.Manifold.batch_boolean([_manifold(p) for p in pieces],
                                              manifold3d.OpType.Add)
    out = solid.to_mesh64()
    return TriangleMesh(np.asarray(out.vert_properties)[:, :3], np.asarray(out.tri_verts))


def rail_footprint(stair: Stair, plan: FloorPlan) -> Polygon | None:
    """The guard rail's plan strip on ``plan`` (the stair's upper floor): along the
    stairwell's edges open to the floor (not against the core's walls), minus where the
    flight arrives and, when a stair leaves this floor there, where it leaves."""
    core = plan.core
    if core is None:
        return None
    edge = stair.polygon.boundary.difference(core.interior.exterior.buffer(1e-6))
    if edge.is_empty or edge.length < 1e-6:
        return None
    arrival = stair.flights[-1].polygon().buffer(1e-6)
    open_parts = [arrival]
    above = plan.stair_up
    if above is not None:
        open_parts.append(above.flights[0].polygon().buffer(1e-6))
    guarded = edge.difference(shapely.union_all(open_parts))
    if guarded.is_empty or guarded.length < 1e-3:
        return None
    strip = shapely.union_all([LineString(line.coords).buffer(RAIL_THICKNESS, cap_style="flat")
                               for line in getattr(guarded, "geoms", [guarded])])
    # the strip stands on the landing side of the edge, not over the stairwell
    strip = strip.difference(stair.polygon).buffer(0)
    if strip.is_empty:
        return None
    return strip if isinstance(strip, Polygon) else max(strip.geoms, key=lambda g: g.area)


def stair_nodes(plan: FloorPlan) -> list[SceneNode]:
    """The solids of the stair that starts on ``plan`` and the rail of the stairwell
    that ends on it."""
    nodes = []
    up = plan.stair_up
    if up is not None:
        nodes.append(SceneNode(f"floor{plan.index}/stair{up.id}", "stair", stair_mesh(up), extras={
            "floor": plan.index, "stair": up.id, "floors": list(up.floors),
            "room": up.rooms[0], "risers": up.risers, "rise": up.rise, "going": up.going}))
    down = plan.stair_down
    if down is not None:
        strip = rail_footprint(down, plan)
        if strip is not None:
            mesh = prism_mesh(strip, plan.floor_y, plan.floor_y + RAIL_HEIGHT)
            nodes.append(SceneNode(f"floor{plan.index}/stairwell{down.id}/rail", "rail", mesh,
                                   extras={"floor": plan.index, "stair": down.id}))
    return nodes
