"""What the renderer needs from a build, from a Scene or read back from its files.

A build renders from its own :class:`~cga.scene.Scene` (``--export render``);
``cga render FILE.scene.json`` renders a finished build from its outputs: the scene JSON
(floors, rooms, node labels) and the glb beside it (the meshes, named by node path).
Both give the same :class:`RenderInputs`, so the rest of the renderer does not know
where its data came from.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import trimesh
from shapely.geometry import Polygon

from cga.errors import UsageError
from cga.mesh import as_trimesh
from cga.scene import Scene, SceneNode
from cga.semantics import instance_ids, node_class

from .raycast import Surface
from .shading import node_colors, surface_colors

__all__ = ["RoomOutline", "FloorOutline", "RenderInputs", "inputs_from_scene",
           "inputs_from_files", "MAX_INSTANCES"]

MAX_INSTANCES = 65_535
"""Most nodes a build may have to be rendered: instance masks are 16-bit PNGs."""


@dataclass(frozen=True)
class RoomOutline:
    """A room's id, type and interior (its free floor before furniture), plan ``(x, z)``."""

    id: int
    type: str | None
    interior: Polygon


@dataclass(frozen=True)
class FloorOutline:
    """A storey as the renderer sees it: walking surface, top, footprint and rooms.

    It has the ``index``, ``floor_y`` and ``footprint`` the occupancy grid reads from a
    floor plan (:func:`cga.checks.occupancy.occupancy_grid`).
    """

    index: int
    floor_y: float
    top: float
    footprint: Polygon
    rooms: tuple[RoomOutline, ...]


@dataclass(frozen=True)
class RenderInputs:
    """A build ready to render: name, seed, storeys, scene nodes and their labelled
    surfaces (one per node, in node order)."""

    name: str
    seed: int
    floors: tuple[FloorOutline, ...]
    nodes: tuple[SceneNode, ...]
    surfaces: tuple[Surface, ...]

    def floor_surfaces(self, index: int) -> list[Surface]:
        """The surfaces of one storey seen from above: its nodes but the roof slab, and
        the storeys below it (seen through a stairwell)."""
        below = {f"floor{f.index}" for f in self.floors if f.index <= index}
        return [s for s in self.surfaces
                if s.path.split("/", 1)[0] in below and s.kind not in ("roof", "ceiling")]


def _surfaces(nodes: tuple[SceneNode, ...], classes: dict[str, int], instances: dict[str, int],
              colors: dict[str, np.ndarray] | None = None) -> tuple[Surface, ...]:
    """The nodes' labelled surfaces; ``colors`` gives a node's triangle colours when its
    mesh no longer carries them (joined from a glb's primitives)."""
    if len(nodes) > MAX_INSTANCES:
        raise UsageError(f"the build has {len(nodes)} nodes; instance masks (16-bit) hold "
                         f"at most {MAX_INSTANCES}")
    colors = colors or {}
    return tuple(Surface(n.path, n.kind, as_trimesh(n.mesh), classes[n.path], instances[n.path],
                         colors[n.path] if n.path in colors else node_colors(n))
                 for n in nodes)


def inputs_from_scene(scene: Scene, nodes: tuple[SceneNode, ...] | list[SceneNode]) -> RenderInputs:
    """The render inputs of a build in memory."""
    nodes = tuple(nodes)
    floors = tuple(
        FloorOutline(plan.index, plan.floor_y, plan.elevation + plan.height, plan.footprint,
                     tuple(RoomOutline(r.id, r.type, r.interior) for r in plan.rooms))
        for plan in scene.floors)
    classes = {n.path: node_class(n) for n in nodes}
    return RenderInputs(scene.name, scene.seed, floors, nodes,
                        _surfaces(nodes, classes, instance_ids(nodes)))


def inputs_from_files(scene_json: Path) -> RenderInputs:
    """The render inputs of a finished build: ``<name>.scene.json`` and ``<name>.glb``
    beside it.

    Raises
    ------
    UsageError
        A file is missing or is not a cga scene document, or the glb lacks a node the
        document lists.
    """
    path = Path(scene_json)
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise UsageError(f"{path}: not a readable scene JSON document ({error})") from None
    if not isinstance(document, dict) or document.get("format") != "cga.scene":
        raise UsageError(f"{path}: not a cga scene document (no \"format\": \"cga.scene\")")
    missing = [key for key in ("name", "seed", "floors", "rooms", "nodes") if key not in document]
    if missing or any("instance_id" not in n for n in document["nodes"]):
        raise UsageError(f"{path}: the document has no semantic labels "
                         f"({', '.join(missing) or 'nodes without instance_id'}); build it "
                         f"again with this version of cga")
    glb = path.with_name(path.name.removesuffix(".scene.json") + ".glb")
    if not glb.is_file():
        raise UsageError(f"{glb}: no such file; cga render reads the glb written beside "
                         f"the scene JSON (cga build writes both by default)")
    parts = _glb_meshes(glb, {entry["path"] for entry in document["nodes"]})
    nodes, colors = [], {}
    for entry in document["nodes"]:
        pieces = parts.get(entry["path"])
        if not pieces:
            raise UsageError(f"{glb}: has no node {entry['path']!r}, which {path.name} lists; "
                             f"were they written by different builds?")
        mesh = pieces[0] if len(pieces) == 1 else _joined(pieces)
        colors[entry["path"]] = np.concatenate([surface_colors(p, entry["kind"]) for p in pieces])
        nodes.append(SceneNode(entry["path"], entry["kind"], mesh, static=entry["static"]))
    classes = {e["path"]: int(e["class_id"]) for e in document["nodes"]}
    instances = {e["path"]: int(e["instance_id"]) for e in document["nodes"]}
    floors = tuple(_floor(f, document["rooms"]) for f in document["floors"])
    node_tuple = tuple(nodes)
    return RenderInputs(str(document["name"]), int(document["seed"]), floors, node_tuple,
                        _surfaces(node_tuple, classes, instances, colors))


def _glb_meshes(path: Path, wanted: set[str]) -> dict[str, list[trimesh.Trimesh]]:
    """The meshes of a glb in world coordinates, by the node path (glTF node name) they
    belong to: a node's own mesh or, for a mesh of several primitives (which trimesh loads
    as child frames, one per primitive), each primitive."""
    loaded: Any
    try:
        loaded = trimesh.load(path, force="scene")
    except Exception as error:  # trimesh raises many types for a damaged file
        raise UsageError(f"{path}: cannot read the glb ({type(error).__name__}: {error})") from None
    parents = loaded.graph.transforms.parents
    out: dict[str, list[trimesh.Trimesh]] = {}
    for name in loaded.graph.nodes_geometry:
        owner = name if name in wanted else parents.get(name)
        if owner not in wanted:
            continue
        matrix, geometry = loaded.graph[name]
        mesh = loaded.geometry[geometry]
        faces = np.asarray(mesh.faces)
        out.setdefault(owner, []).append(trimesh.Trimesh(
            vertices=trimesh.transform_points(mesh.vertices, matrix),
            faces=faces[:, ::-1] if np.linalg.det(matrix[:3, :3]) < 0 else faces,
            visual=mesh.visual, process=False))
    return out


def _joined(pieces: list[trimesh.Trimesh]) -> trimesh.Trimesh:
    """One mesh of several, triangles in order (without their visuals)."""
    offsets = np.cumsum([0] + [len(p.vertices) for p in pieces[:-1]])
    return trimesh.Trimesh(np.vstack([p.vertices for p in pieces]),
                           np.vstack([np.asarray(p.faces) + o for p, o in zip(pieces, offsets)]),
                           process=False)


def _polygon(data: dict[str, Any]) -> Polygon:
    if not data["exterior"]:
        return Polygon()
    return Polygon(data["exterior"], data["holes"])


def _floor(data: dict[str, Any], rooms: list[dict[str, Any]]) -> FloorOutline:
    index = int(data["index"])
    return FloorOutline(
        index, float(data["floor_y"]), float(data["elevation"]) + float(data["height"]),
        _polygon(data["footprint"]),
        tuple(RoomOutline(int(r["id"]), r["type"], _polygon(r["interior"]))
              for r in rooms if r["floor"] == index))
