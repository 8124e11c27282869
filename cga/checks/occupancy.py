"""Occupancy grids: what a wheeled robot bumps into on one floor, in cells.

A ground robot collides with whatever stands between its wheels and its top: walls, and
furniture that reaches into that height band (a table top at 0.75 m blocks a robot of
1.2 m, a rug does not). For one floor plan, :func:`occupancy_grid` takes every scene node
whose solid meets the band (relative to the floor's walking surface), projects the slice
of the solid inside the band onto the floor exactly (convex furniture parts directly;
rectilinear solids, such as walls with openings, on the grid of their own planes
(:mod:`cga.checks._rectilinear`); other solids with manifold3d: clip by two planes, then
take the shadow), and rasterises the shadows. A wall keeps its door gaps open
because the slice of the band through a door opening is empty, and a window with its
sill inside the band stays closed because the wall below the sill is in the band.

Cells and frames: the array follows the ROS map convention (``map_server``): row 0 is the
top of the image, i.e. the largest ROS ``y``; ROS ``(x, y)`` is world ``(x, −z)``
(docs/architecture.md, "Units and frames"), so rows run along world ``+z`` and columns
along ``+x``. ``origin`` is the ROS position of the lower-left corner of the lower-left
cell, as in a map YAML file. Shadows are drawn with their outlines, so a cell an obstacle
crosses is occupied and thin parts never vanish; positions are accurate to one cell.

Static furniture (rugs, window frames) is not an obstacle: rugs are walked over and a
window frame stands in a wall. A door leaf is one, where the build leaves it (docs/outputs.md):
a closed leaf shuts its doorway on the map, an open one stands against its jamb; its
shadow is that of its collision box (:mod:`cga.doors`), the one every robot format uses.
``include_doors=False`` draws the building with every door open, which the navigability
check uses to tell rooms cut off from rooms behind a door the robot must open.
Stairs are obstacles except their floor landings, whatever part of them lies in the
band (:func:`stair_obstacles`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from cga.mesh import MeshLike
from cga.model import FloorPlan
from cga.scene import MeshArrays, NodeKind, SceneNode

from ._raster import Patch, polygon_patches
from ._rectilinear import rectilinear_shadows, union_by_owner
from ._solids import as_manifold

__all__ = [
    "FloorExtent",
    "Obstacle",
    "OccupancyGrid",
    "band_footprint",
    "band_footprints",
    "occupancy_grid",
    "obstacle_nodes",
    "stair_obstacles",
]

_TO_PLAN = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, -1.0, 0.0, 0.0]])
"""World (x, y, z) → (x, z, −y): a proper rotation whose xy plane is the plan (x, z), so a
manifold3d projection along its z axis is the view from above."""


_SHEET = 1e-3
"""Half-thickness (m) given to the triangles of open meshes, whose shadow may be a line."""


class FloorExtent(Protocol):
    """What a grid needs of a floor: a :class:`~cga.model.FloorPlan`, or the outline a
    renderer reads back from a scene JSON (:class:`cga.render.inputs.FloorOutline`)."""

    @property
    def index(self) -> int: ...

    @property
    def floor_y(self) -> float: ...

    @property
    def footprint(self) -> Polygon: ...


@dataclass(frozen=True)
class Obstacle:
    """One scene node's shadow in the band: ``footprint`` in plan ``(x, z)`` metres."""

    path: str
    kind: NodeKind
    footprint: BaseGeometry
    room: int | None = None
    """The room a furniture item stands in (None for the structure)."""
    door: int | None = None
    """The id of the door whose leaf this is (None for anything else)."""


@dataclass(frozen=True)
class OccupancyGrid:
    """A floor's occupancy in cells of ``resolution`` metres (ROS map convention).

    Attributes
    ----------
    occupied
        ``bool[rows, cols]``: a cell an obstacle's shadow covers or crosses.
    free_mask
        ``bool[rows, cols]``: a cell inside the floor's footprint (the building); a
        ROS map shows the other cells as unknown.
    origin
        ROS ``(x, y)`` of the lower-left corner of the lower-left cell (row ``rows−1``,
        column 0), as in a map YAML ``origin``.
    resolution
        Cell size (m).
    floor
        Index of the floor plan.
    band
        World heights ``(y0, y1)`` of the robot's band on this floor.
    obstacles
        The nodes drawn, each with its band shadow.
    """

    occupied: np.ndarray
    free_mask: np.ndarray
    origin: tuple[float, float]
    resolution: float
    floor: int
    band: tuple[float, float]
    obstacles: tuple[Obstacle, ...] = ()
    cells: dict[int, list[Patch]] = field(default_factory=dict, compare=False, repr=False)
    """The cells of each obstacle (by its index in ``obstacles``), rasterised by the
    first :meth:`occupied_by` that asks for it and kept for the next."""

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.occupied.shape[0]), int(self.occupied.shape[1]))

    @property
    def x_min(self) -> float:
        """World x of the grid's left edge."""
        return self.origin[0]

    @property
    def z_min(self) -> float:
        """World z of the grid's top edge (row 0): ROS ``y`` grows downwards in z."""
        return -(self.origin[1] + self.shape[0] * self.resolution)

    def world_to_cell(self, x: float, z: float) -> tuple[int, int]:
        """``(row, col)`` of the cell holding world point ``(x, z)``; it may lie outside
        the grid (see :meth:`in_bounds`)."""
        return (math.floor((z - self.z_min) / self.resolution),
                math.floor((x - self.x_min) / self.resolution))

    def cell_to_world(self, row: float, col: float) -> tuple[float, float]:
        """World ``(x, z)`` of the centre of cell ``(row, col)``."""
        return (self.x_min + (col + 0.5) * self.resolution,
                self.z_min + (row + 0.5) * self.resolution)

    def in_bounds(self, row: int, col: int) -> bool:
        return 0 <= row < self.shape[0] and 0 <= col < self.shape[1]

    def rasterise(self, geometry: BaseGeometry) -> np.ndarray:
        """``bool[rows, cols]`` of the cells a plan-space ``(x, z)`` geometry covers or
        crosses (outline included, like the obstacles)."""
        mask = np.zeros(self.shape, dtype=bool)
        _paint(mask, geometry, self.x_min, self.z_min, self.resolution)
        return mask

    def occupied_by(self, paths: Iterable[str]) -> np.ndarray:
        """The cells occupied by the obstacles with these node paths only."""
        wanted = set(paths)
        chosen = [k for k, obstacle in enumerate(self.obstacles) if obstacle.path in wanted]
        missing = [k for k in chosen if k not in self.cells]
        drawn = polygon_patches(self.shape, [self.obstacles[k].footprint for k in missing],
                                self.x_min, self.z_min, self.resolution)
        self.cells.update(zip(missing, drawn))
        mask = np.zeros(self.shape, dtype=bool)
        for k in chosen:
            _apply(mask, self.cells[k])
        return mask


def obstacle_nodes(nodes: Sequence[SceneNode], *, include_doors: bool = True) -> list[SceneNode]:
    """Nodes that can block a robot: the structure, the solid (dynamic) furniture and,
    with ``include_doors``, the door leaves."""
    return [n for n in nodes
            if not (n.kind == "furniture" and n.static)
            or (include_doors and n.door is not None)]


def band_footprint(node: SceneNode, y0: float, y1: float) -> BaseGeometry:
    """The shadow, in plan ``(x, z)``, of the part of ``node`` between heights ``y0`` and
    ``y1`` (an empty geometry when none of it is).

    A furniture node made of convex parts is the union of its parts' shadows, computed
    directly (the slice of a convex solid between two planes is convex, so its shadow is
    the hull of its vertices in the band and of its edges' crossings with the planes).
    A rectilinear solid's shadow is the union of the cells of its plan grid that it fills
    in the band (:mod:`cga.checks._rectilinear`: manifold3d's region, to the bit). Other
    meshes are clipped and projected with manifold3d. A mesh that is not a
    watertight solid (an open surface) is taken triangle by triangle: the shadow of its
    triangles clipped to the band, thickened by 1 mm so that a vertical sheet still
    blocks the cells it crosses.
    """
    return band_footprints([node], y0, y1)[0]


def band_footprints(nodes: Sequence[SceneNode], y0: float, y1: float) -> list[BaseGeometry]:
    """:func:`band_footprint` of every node, in order; the convex parts of all the
    nodes are sliced and hulled in one vectorised pass (:func:`_convex_shadows`), and
    the rectilinear solids (walls, slabs, stairs) are shadowed in another
    (:mod:`cga.checks._rectilinear`: the same regions as manifold3d's)."""
    out: list[BaseGeometry | None] = [None] * len(nodes)
    convex: list[int] = []
    solids: list[int] = []
    for k, node in enumerate(nodes):
        lo, hi = node.mesh.bounds
        if hi[1] <= y0 or lo[1] >= y1:
            out[k] = Polygon()
        elif node.parts and node.convex_parts:
            convex.append(k)
        else:
            solids.append(k)
    shadows = _convex_shadows([[p for p in nodes[k].parts if len(p.faces)] for k in convex],
                              y0, y1)
    shadows += rectilinear_shadows([nodes[k].mesh for k in solids], y0, y1)
    for k, shadow in zip(convex + solids, shadows):
        out[k] = shadow if shadow is not None else _solid_footprint(nodes[k].mesh, y0, y1)
    return [g if g is not None else Polygon() for g in out]


def _solid_footprint(mesh: MeshLike, y0: float, y1: float) -> BaseGeometry:
    """The band shadow of a mesh that is not made of convex parts: clipped and projected
    with manifold3d, or triangle by triangle when it is not a watertight solid."""
    solid = as_manifold(mesh)
    if solid is None:
        return _sheet_footprint(mesh, y0, y1)
    band = (solid.transform(_TO_PLAN)
            .trim_by_plane((0.0, 0.0, 1.0), -y1)
            .trim_by_plane((0.0, 0.0, -1.0), y0))
    if band.is_empty():
        return Polygon()
    polygons = [_polygon(piece.to_polygons()) for piece in band.project().decompose()]
    polygons = [p for p in polygons if not p.is_empty]
    if not polygons:
        return Polygon()
    return polygons[0] if len(polygons) == 1 else shapely.MultiPolygon(polygons)


def _band_points(parts: Sequence[MeshArrays], y0: float,
                 y1: float) -> tuple[np.ndarray, np.ndarray]:
    """The plan points whose hull is the shadow of the slice of each convex part between
    heights ``y0`` and ``y1`` (its vertices in the band and its edges' crossings with
    the two planes), all parts at once: ``(points, owner)`` with the index of each
    point's part, grouped by part, in the order vertices, lower crossings, upper ones."""
    if not parts:
        return np.zeros((0, 2)), np.zeros(0, dtype=np.int64)
    vertices = [np.asarray(part.vertices, dtype=float) for part in parts]
    faces = [np.asarray(part.faces) for part in parts]
    sizes = np.array([len(v) for v in vertices], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    points = np.concatenate(vertices)
    vertex_owner = np.repeat(np.arange(len(parts)), sizes)
    edges = (np.concatenate(faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
             + np.repeat(starts, [3 * len(f) for f in faces])[:, None])
    edge_owner = vertex_owner[edges[:, 0]]
    y = points[:, 1]
    inside = (y >= y0) & (y <= y1)
    found, owner = [points[inside][:, [0, 2]]], [vertex_owner[inside]]
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    for h in (y0, y1):
        crossing = (a[:, 1] - h) * (b[:, 1] - h) < 0
        t = (h - a[crossing, 1]) / (b[crossing, 1] - a[crossing, 1])
        found.append((a[crossing] + t[:, None] * (b[crossing] - a[crossing]))[:, [0, 2]])
        owner.append(edge_owner[crossing])
    ids = np.concatenate(owner)
    order = np.argsort(ids, kind="stable")
    return np.concatenate(found)[order], ids[order]


def _convex_shadows(groups: Sequence[Sequence[MeshArrays]], y0: float,
                    y1: float) -> list[BaseGeometry]:
    """For each group of convex parts (one node's), the union of the shadows of the
    slices of its parts between heights ``y0`` and ``y1``: each the hull of
    :func:`_band_points`, a degenerate hull (a part seen edge-on) thickened by
    :data:`_SHEET`. The hulls of all groups are made in one vectorised call and united
    per group in another.

    Each part's points go to GEOS as a line string, not a multipoint: a hull is made
    of the distinct points in their order either way, and a line string is made
    without a point geometry per point (a part with a single point has it twice).
    A group one of whose hulls is an axis-aligned rectangle holding all the others (a
    table top over its legs) is that rectangle, without a union: the same region,
    which is all a grid's cells depend on when it is rectilinear."""
    parts = [part for group in groups for part in group]
    group_of = np.repeat(np.arange(len(groups)), [len(g) for g in groups])
    points, owner = _band_points(parts, y0, y1)
    kept, owner = np.unique(owner, return_inverse=True)  # parts with points, in order
    twice = np.where(np.bincount(owner)[owner] == 1, 2, 1)
    hulls = shapely.convex_hull(shapely.linestrings(np.repeat(points, twice, axis=0),
                                                    indices=np.repeat(owner, twice)))
    flat = shapely.get_type_id(hulls) != shapely.GeometryType.POLYGON
    hulls[flat] = shapely.buffer(hulls[flat], _SHEET)
    rows = group_of[kept]
    whole = _covering_boxes(hulls, rows, len(groups))
    rest = whole[rows] < 0
    shadows = union_by_owner(hulls[rest], rows[rest], len(groups))
    shadows[whole >= 0] = hulls[whole[whole >= 0]]
    return list(shadows)


def _covering_boxes(hulls: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    """For each owner ``0 … count − 1`` of ``hulls`` (grouped by owner), the index of a
    hull that is an axis-aligned rectangle as large as the bounding box of all its
    owner's hulls (so it holds them all), or −1."""
    xz, ring = shapely.get_coordinates(hulls, return_index=True)
    slanted = (ring[1:] == ring[:-1]) & np.all(np.diff(xz, axis=0) != 0, axis=1)
    box = ((shapely.get_num_coordinates(hulls) == 5)
           & (np.bincount(ring[1:][slanted], minlength=len(hulls)) == 0))
    bounds = shapely.bounds(hulls)
    low = np.full((count, 2), np.inf)
    high = np.full((count, 2), -np.inf)
    np.minimum.at(low, owner, bounds[:, :2])
    np.maximum.at(high, owner, bounds[:, 2:])
    covers = box & np.all(bounds == np.hstack([low, high])[owner], axis=1)
    index = np.flatnonzero(covers)
    groups, first = np.unique(owner[index], return_index=True)  # the first, where several
    whole = np.full(count, -1)
    whole[groups] = index[first]
    return whole


def _sheet_footprint(mesh: MeshLike, y0: float, y1: float) -> BaseGeometry:
    """The shadow of an open mesh's triangles between heights ``y0`` and ``y1``
    (trimesh's plane slicing: open meshes are rare, a massing grammar's faces)."""
    import trimesh

    part = trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, process=False)
    part = trimesh.intersections.slice_mesh_plane(part, (0.0, 1.0, 0.0), (0.0, y0, 0.0))
    if len(part.faces):
        part = trimesh.intersections.slice_mesh_plane(part, (0.0, -1.0, 0.0), (0.0, y1, 0.0))
    if not len(part.faces):
        return Polygon()
    triangles = shapely.polygons(np.asarray(part.triangles)[:, :, [0, 2]])
    return shapely.union_all(shapely.buffer(triangles, _SHEET))


def _polygon(rings: Sequence[np.ndarray]) -> Polygon:
    """One connected piece of a cross-section as a polygon: manifold3d (Clipper2) gives its
    outer ring counter-clockwise and its holes clockwise."""
    outer: np.ndarray | None = None
    holes = []
    for ring in rings:
        if len(ring) < 3:
            continue
        x, y = ring[:, 0], ring[:, 1]
        area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        if area > 0:
            outer = ring
        elif area < 0:
            holes.append(ring)
    if outer is None:
        return Polygon()
    polygon = Polygon(outer, holes)
    return polygon if polygon.is_valid else polygon.buffer(0)


MAX_GRID_CELLS = 2_000_000
"""Most cells of one occupancy grid (docs/limits.md): about 70 m × 70 m at 5 cm. A larger
floor gets coarser cells (:func:`grid_resolution`) instead of gigabytes of raster."""


def grid_resolution(resolution: float, width: float, depth: float) -> float:
    """``resolution``, or the finest coarser cell size (a whole multiple of 1 mm) that
    keeps a ``width`` × ``depth`` m grid within :data:`MAX_GRID_CELLS`."""
    if (width / resolution + 1) * (depth / resolution + 1) <= MAX_GRID_CELLS:
        return resolution
    coarse = math.sqrt(width * depth / MAX_GRID_CELLS)
    coarse = max(resolution, math.ceil(coarse * 1000) / 1000)
    while (width / coarse + 1) * (depth / coarse + 1) > MAX_GRID_CELLS:
        coarse *= 1.01
    return coarse


def occupancy_grid(plan: FloorExtent, nodes: Sequence[SceneNode], *, resolution: float = 0.05,
                   band: tuple[float, float] = (0.05, 1.2), margin: float = 0.5,
                   include_furniture: bool = True, include_doors: bool = True) -> OccupancyGrid:
    """Rasterise one floor's obstacles in the robot's height band.

    Parameters
    ----------
    plan
        The floor plan (or any :class:`FloorExtent`); its footprint sets the grid's
        extent and ``free_mask``, its walking surface (``floor_y``) the base of the band.
    nodes
        The scene's nodes (world space); those outside the band are skipped, so the
        whole scene can be passed for every floor.
    resolution
        Cell size (m); coarser when the floor would need more than
        :data:`MAX_GRID_CELLS` cells (the grid's ``resolution`` says which was used).
    band
        Heights above the walking surface (m) between which an obstacle blocks the robot.
    margin
        Free border (m) around the footprint, so the outside of a front door is on the map.
    include_furniture
        False draws the structure only (what the building itself allows).
    include_doors
        False leaves the door leaves out (every door open).

    Returns
    -------
    OccupancyGrid

    Raises
    ------
    ValueError
        ``resolution`` or ``margin`` is not positive, or the band is empty.

    Notes
    -----
    One vectorised pass over the rectilinear structure nodes (an exact clip-and-project
    for any other), one over all the furniture's convex parts, and the shadows' cells,
    kept for :meth:`OccupancyGrid.occupied_by`, filled by Pillow's rule in one numpy pass
    (Pillow itself draws the few with a slanted edge or a hole: :mod:`cga.checks._raster`);
    about 15 ms of CPU for a furnished 14 m × 10 m floor at 5 cm.
    """
    if not resolution > 0:
        raise ValueError(f"occupancy_grid: resolution must be positive, got {resolution!r}")
    if not margin >= 0:
        raise ValueError(f"occupancy_grid: margin must not be negative, got {margin!r}")
    if not band[1] > band[0]:
        raise ValueError(f"occupancy_grid: band {band} must be (low, high) with low < high")
    y0, y1 = plan.floor_y + band[0], plan.floor_y + band[1]
    minx, minz, maxx, maxz = plan.footprint.bounds
    x_min, z_min = minx - margin, minz - margin
    resolution = grid_resolution(resolution, maxx + margin - x_min, maxz + margin - z_min)
    cols = max(1, math.ceil((maxx + margin - x_min) / resolution - 1e-9))
    rows = max(1, math.ceil((maxz + margin - z_min) / resolution - 1e-9))
    origin = (x_min, -(z_min + rows * resolution))
    occupied = np.zeros((rows, cols), dtype=bool)
    free_mask = np.zeros((rows, cols), dtype=bool)
    _paint(free_mask, plan.footprint, x_min, z_min, resolution)
    extent = shapely.box(x_min, z_min, x_min + cols * resolution, z_min + rows * resolution)
    candidates = _meeting([node for node in obstacle_nodes(nodes, include_doors=include_doors)
                           if include_furniture or node.kind != "furniture"
                           or node.door is not None], y0, y1, extent)
    obstacles = [Obstacle(node.path, node.kind, footprint,
                          node.item.room if node.item is not None else None,
                          node.door.door if node.door is not None else None)
                 for node, footprint in zip(candidates, band_footprints(candidates, y0, y1))
                 if not footprint.is_empty]
    # a floor read back from files has its stairs as meshes among the nodes already
    if isinstance(plan, FloorPlan):
        obstacles.extend(stair_obstacles(plan))
    # occupied_by rasterises in the grid's own frame, whose z origin differs from z_min
    # by round-off: an obstacle's cells drawn here are kept for it when no vertex of
    # the obstacle changes row between the two frames (Pillow then draws the same cells)
    footprints = [obstacle.footprint for obstacle in obstacles]
    drawn = polygon_patches(occupied.shape, footprints, x_min, z_min, resolution)
    for patches in drawn:
        _apply(occupied, patches)
    kept = _same_rows(footprints, z_min, -(origin[1] + rows * resolution), resolution)
    cells = {k: patches for k, patches in enumerate(drawn) if kept[k]}
    return OccupancyGrid(occupied=occupied, free_mask=free_mask, origin=origin,
                         resolution=resolution, floor=plan.index, band=(y0, y1),
                         obstacles=tuple(obstacles), cells=cells)


def stair_obstacles(plan: FloorPlan) -> list[Obstacle]:
    """The stairs on this floor as obstacles, all but their floor landings (DESIGN §12):
    the flights and half landing of the stair leaving it (``floor{i}/stair{k}/flights``)
    and the stairwell of the stair arriving (``floor{i}/stairwell{k}``), both of kind
    ``"stair"``. A wheeled robot cannot drive up steps or over the hole; it
    changes floors at the landings (:mod:`cga.checks.navigability`)."""
    out = []
    up, down = plan.stair_up, plan.stair_down
    if up is not None:
        out.append(Obstacle(f"floor{plan.index}/stair{up.id}/flights", "stair", up.polygon))
    if down is not None:
        out.append(Obstacle(f"floor{plan.index}/stairwell{down.id}", "stair", down.polygon))
    return out


def _meeting(nodes: Sequence[SceneNode], y0: float, y1: float,
             extent: BaseGeometry) -> list[SceneNode]:
    """The nodes with triangles whose bounding box meets the band and the grid's extent
    (one vectorised test of all the boxes against the extent)."""
    nodes = [node for node in nodes if len(node.mesh.faces)]
    if not nodes:
        return []
    lo, hi = np.array([node.mesh.bounds for node in nodes]).transpose(1, 0, 2)
    meets = (~((hi[:, 1] <= y0) | (lo[:, 1] >= y1))
             & shapely.intersects(extent, shapely.box(lo[:, 0], lo[:, 2], hi[:, 0], hi[:, 2])))
    return [node for node, keep in zip(nodes, meets.tolist()) if keep]


def _paint(mask: np.ndarray, geometry: BaseGeometry, x_min: float, z_min: float,
           resolution: float) -> None:
    """Set the cells of ``mask`` that ``geometry`` (plan x, z) covers or crosses."""
    _apply(mask, polygon_patches(mask.shape, [geometry], x_min, z_min, resolution)[0])


def _same_rows(geometries: Sequence[BaseGeometry], z_a: float, z_b: float,
               resolution: float) -> np.ndarray:
    """For each geometry, whether every vertex lies in the same row of cells (as
    :func:`~cga.checks._raster.polygon_patches` computes it) with the grid's top edge
    at ``z_a`` and at ``z_b``."""
    xz, owner = shapely.get_coordinates(np.array(geometries, dtype=object), return_index=True)
    z = xz[:, 1]
    moved = np.floor((z - z_a) / resolution) != np.floor((z - z_b) / resolution)
    return np.bincount(owner[moved], minlength=len(geometries)) == 0


def _apply(mask: np.ndarray, patches: Sequence[Patch]) -> None:
    for r0, r1, c0, c1, cells in patches:
        mask[r0:r1, c0:c1] |= cells
