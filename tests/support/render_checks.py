"""Independent checks of rendered views against the scene JSON.

Reads a view the way a training loader does: the PNGs with PIL, the camera JSON's
intrinsics and OpenCV ``camera_to_world``, depth in millimetres along the optical axis.
The geometry it compares with is computed here from the scene JSON (walls from their
segments, thickness and openings; rooms from their interiors) and, for the furniture's
shadows on the floor, from the glb's triangles projected with shapely: never from the
renderer's code or its ray casts.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import shapely
from PIL import Image
from shapely.geometry import Point, Polygon


def load_view(folder: Path, view: str) -> dict:
    """The images (numpy arrays) and camera JSON of one view."""
    camera = json.loads((folder / f"{view}.camera.json").read_text())
    images = {kind: np.asarray(Image.open(folder / f"{view}.{kind}.png"))
              for kind in ("rgb", "depth", "semantic", "instance")}
    return {"camera": camera, **images}


def pixel_points(view: dict, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """World points of pixels ``(rows, cols)`` from their depth (OpenCV pinhole or
    orthographic model of the camera JSON)."""
    camera = view["camera"]
    k = camera["intrinsics"]
    z = view["depth"][rows, cols].astype(float) / 1000.0
    x = (cols - k["cx"]) / k["fx"]
    y = (rows - k["cy"]) / k["fy"]
    if camera["projection"] == "perspective":
        local = np.column_stack([x * z, y * z, z])
    else:
        local = np.column_stack([x, y, z])
    matrix = np.array(camera["opencv"]["camera_to_world"])
    return local @ matrix[:3, :3].T + matrix[:3, 3]


def _inward(wall: dict, footprint: Polygon) -> np.ndarray:
    start, end = np.array(wall["start"]), np.array(wall["end"])
    u = (end - start) / wall["length"]
    normal = np.array([-u[1], u[0]])
    middle = (start + end) / 2
    return normal if footprint.contains(Point(*(middle + normal * 0.05))) else -normal


def wall_surface_distance(points: np.ndarray, document: dict) -> np.ndarray:
    """Distance of each world point to the nearest visible face of a wall of any floor
    (a camera may see the storey below through a stairwell): a long face, or the reveal,
    sill or head of an opening, of a wall whose solid (grown by 5 cm) holds the point;
    inf when no wall's solid is near it."""
    plans = {f["index"]: f for f in document["floors"]}
    best = np.full(len(points), np.inf)
    grow = 0.05
    for wall in document["walls"]:
        plan = plans[wall["floor"]]
        footprint = Polygon(plan["footprint"]["exterior"], plan["footprint"]["holes"])
        y0, top = plan["floor_y"], plan["elevation"] + plan["height"]
        start, end = np.array(wall["start"]), np.array(wall["end"])
        u = (end - start) / wall["length"]
        t = wall["thickness"]
        if wall["outer"]:
            n, (a, b) = _inward(wall, footprint), (0.0, t)
        else:
            n, (a, b) = np.array([-u[1], u[0]]), (-t / 2, t / 2)
        rel = points[:, [0, 2]] - start
        s, o, y = rel @ u, rel @ n, points[:, 1]
        near = ((s > -t - grow) & (s < wall["length"] + t + grow) & (o > a - grow)
                & (o < b + grow) & (y > y0 - grow) & (y < top + grow))
        d = np.minimum(np.abs(o - a), np.abs(o - b))
        for opening in wall["openings"]:
            lo, hi = opening["center"] - opening["width"] / 2, opening["center"] + opening["width"] / 2
            sill, head = y0 + opening["sill"], y0 + opening["sill"] + opening["height"]
            inside = (s > lo - grow) & (s < hi + grow) & (y > sill - grow) & (y < head + grow)
            faces = np.min([np.abs(s - lo), np.abs(s - hi), np.abs(y - sill), np.abs(y - head)],
                           axis=0)
            d = np.where(inside, np.minimum(d, faces), d)
        best = np.where(near, np.minimum(best, d), best)
    return best


def _stands_on_the_floor(path: str, floor: int) -> bool:
    """Furniture (``…/furniture/…``) and stairs (``floor{i}/stair{k}``,
    ``floor{i}/stairwell{k}/rail``) of ``floor``, by node path."""
    parts = path.split("/")
    return parts[0] == f"floor{floor}" and (
        "furniture" in parts or any(p.startswith("stair") for p in parts[1:]))


def furniture_shadows(glb: Path, floor: int) -> shapely.Geometry:
    """The union of the plan shadows (x, z) of every triangle of the furniture and stair
    nodes of ``floor`` in a build's glb (node names are node paths), read with trimesh."""
    import trimesh

    scene = trimesh.load(glb, force="scene")
    triangles = []
    for name in scene.graph.nodes_geometry:
        if not _stands_on_the_floor(name, floor):
            continue
        matrix, geometry = scene.graph[name]
        mesh = scene.geometry[geometry]
        world = trimesh.transform_points(mesh.vertices, matrix)[np.asarray(mesh.faces)]
        triangles.append(world[:, :, [0, 2]])
    if not triangles:
        return Polygon()
    flat = np.concatenate(triangles)
    polygons = shapely.polygons(flat)
    polygons = polygons[shapely.area(polygons) > 1e-10]
    return shapely.union_all(polygons)


def floor_pixel_areas(view: dict, document: dict, floor_class: int,
                      shadows: shapely.Geometry) -> dict[int, tuple[float, float]]:
    """Room id → (floor-class pixel area, free floor area) for the rooms of an
    orthographic top-down view: the free area is the room's interior minus the
    furniture's and stairs' ``shadows`` (:func:`furniture_shadows`) and minus the
    stairwell, the hole in the floor's slab (``floors[].stairwell``)."""
    camera = view["camera"]
    assert camera["projection"] == "orthographic"
    k = camera["intrinsics"]
    rows, cols = np.indices(view["semantic"].shape)
    matrix = np.array(camera["opencv"]["camera_to_world"])
    local = np.stack([(cols - k["cx"]) / k["fx"], (rows - k["cy"]) / k["fy"],
                      np.zeros(rows.shape)], axis=-1)
    world = local @ matrix[:3, :3].T + matrix[:3, 3]
    pixel_area = 1.0 / (k["fx"] * k["fy"])
    is_floor = view["semantic"] == floor_class
    plan = next(f for f in document["floors"] if f["index"] == camera["floor"])
    well = plan.get("stairwell")
    # through the stairwell the view sees the storey below (the floor in a U stair's well)
    below = np.zeros(rows.shape, dtype=bool)
    if well:
        hole = Polygon(well["exterior"], well["holes"])
        shadows = shapely.union(shadows, hole)
        below = shapely.contains_xy(hole, world[..., 0], world[..., 2])
    out = {}
    for room in (r for r in document["rooms"] if r["floor"] == camera["floor"]):
        interior = Polygon(room["interior"]["exterior"], room["interior"]["holes"])
        free = interior.difference(shadows)
        inside = shapely.contains_xy(interior, world[..., 0], world[..., 2]) & ~below
        out[room["id"]] = (float((inside & is_floor).sum()) * pixel_area, float(free.area))
    return out
