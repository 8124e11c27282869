"""``<name>.glb``: the building as binary glTF 2.0 (docs/outputs.md).

A node tree that follows the node paths: ``floor1/room3_Kitchen/wall2`` is a child of
the group node ``floor1/room3_Kitchen``, itself a child of ``floor1``; every node keeps
its full path as its name. Group nodes (floors, rooms, ``…/furniture``, the parts of a
massing grammar's shape path) carry no mesh and no transform; a floor's node carries the
floor's facts (index, elevation, height), a room's its type, area and id.

Structure (walls, slabs, masses) is meshed in the building's frame. Every item is a node
with its own pivot: a furniture item at the centre of its footprint on the floor, turned
by its quarter turns; a door leaf at its hinge, turned by the build's door angle
(:mod:`cga.doors`). Their meshes are given in that local frame, so instances of the same
model (same size) share one glTF mesh, made (normals and all) once, and a viewer or
Blender turns an item or swings a door about the right point. Meshes carry normals. A node's ``extras`` are its semantic
labels plus its ``kind`` and ``static`` flag, its semantic ``class_id`` and ``class`` and
its ``instance_id`` (:mod:`cga.semantics`); y up, metres.

Every primitive has a glTF metallic-roughness material: a node's mesh has one primitive
per material of the node (:mod:`cga.appearance`: wall paint per room, floors per room,
each furniture part's material), base colours linear as glTF wants them; see-through
materials (window glass) blend. Each room's ceiling lights are nodes
(``floor0/room3_Office/light0``) that point at ``KHR_lights_punctual`` point lights
(candela, colour of their temperature; docs/appearance.md).

The bytes are a pure function of the scene: nodes in the given order, no timestamps,
extras with sorted keys. The same seed gives a byte-identical file (tested).
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from cga.appearance.material import Material
from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.model import FloorPlan, rotation_matrix
from cga.scene import Scene, SceneNode
from cga.semantics import class_names, instance_ids, node_class

from .palette import kind_material

__all__ = ["scene_as_glb", "export_glb", "json_safe", "node_pivot"]

_IDENTITY = np.eye(4)

_PLAIN = frozenset({str, int, float, bool, type(None)})
"""Types :func:`json_safe` returns as they are."""


def json_safe(value: Any) -> Any:
    """``value`` as plain JSON data: numpy scalars/arrays → numbers/lists, tuples → lists,
    mappings with sorted string keys, sets as sorted lists.

    Raises
    ------
    TypeError
        A value with no JSON form (the message names its type).
    """
    kind = type(value)
    if kind in _PLAIN:  # the common case first: isinstance against ABCs is slow
        return value
    if kind is dict:
        return {str(k): json_safe(value[k]) for k in sorted(value, key=str)}
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, float)):
        return value
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist())
    if isinstance(value, Mapping):
        return {str(k): json_safe(value[k]) for k in sorted(value, key=str)}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, (set, frozenset)):
        return sorted(json_safe(v) for v in value)
    raise TypeError(f"cannot store a {type(value).__name__} in glTF extras")


def node_pivot(node: SceneNode) -> np.ndarray:
    """4×4 world transform of a node's own frame: a door leaf's hinge frame at its angle,
    a furniture item's footprint centre on its floor turned by its quarter turns, the
    identity for structure."""
    if node.door is not None:
        return node.door.frame()
    if node.kind != "furniture":
        return np.eye(4)
    (x0, y0, z0), (x1, _, z1) = node.mesh.bounds
    matrix = np.eye(4)
    matrix[:3, :3] = rotation_matrix(node.item.rotation if node.item is not None else 0)
    matrix[:3, 3] = ((x0 + x1) / 2, y0, (z0 + z1) / 2)
    return matrix


def _local_vertices(node: SceneNode, inverse: np.ndarray | None) -> np.ndarray:
    """The node's vertices in the frame of its pivot, given as the pivot's ``inverse``
    (None: the identity, for structure), on a micrometre grid, so instances of one model
    land on identical local vertices."""
    vertices = np.asarray(node.mesh.vertices, dtype=float)
    if inverse is not None:
        vertices = vertices @ inverse[:3, :3].T + inverse[:3, 3]
    return np.round(vertices, 6) + 0.0


def _local_transforms(pivots: Sequence[np.ndarray]) -> list[np.ndarray | None]:
    """The inverse of each pivot, None for the identity (:func:`_local_vertices`): one
    batched :func:`numpy.linalg.inv` (the same LAPACK solve per matrix as one call each)."""
    moved = [i for i, pivot in enumerate(pivots) if not np.array_equal(pivot, _IDENTITY)]
    out: list[np.ndarray | None] = [None] * len(pivots)
    if moved:
        for i, inverse in zip(moved, np.linalg.inv(np.stack([pivots[i] for i in moved]))):
            out[i] = inverse
    return out


def _source_key(node: SceneNode, vertices: np.ndarray) -> tuple[bytes, tuple[Material, ...]] | None:
    """What a dressed node's glTF mesh is made of (local vertices, faces, each face's
    material): nodes with equal keys get equal meshes, so the mesh is made once (the
    instances of a model share it). None for a node without materials."""
    if not node.materials or node.face_materials is None:
        return None
    digest = hashlib.sha1(np.ascontiguousarray(vertices).tobytes())
    digest.update(np.ascontiguousarray(node.mesh.faces, dtype=np.int64).tobytes())
    digest.update(np.ascontiguousarray(node.face_materials, dtype=np.int64).tobytes())
    return digest.digest(), node.materials


def _local_meshes(node: SceneNode, vertices: np.ndarray, normals: np.ndarray,
                  looks: _Looks) -> list[Any]:
    """The node's mesh at its local ``vertices`` (:func:`_local_vertices`) with their
    ``normals`` (:func:`_vertex_normals`), without metadata (which trimesh would write as
    mesh extras): one mesh per material of the node (:attr:`SceneNode.materials`), each
    with its PBR material, which become the primitives of one glTF mesh. A node without
    materials (not dressed) keeps its own colours, or gets its kind's colour."""
    import trimesh

    source = node.mesh
    faces = np.asarray(source.faces, dtype=np.int64)
    if not node.materials or node.face_materials is None:
        visual = source.visual
        if visual is None or visual.kind is None:
            visual = looks.visual(kind_material(node.kind))
        else:
            visual = visual.copy()
        return [trimesh.Trimesh(vertices=vertices, faces=faces, vertex_normals=normals,
                                visual=visual, process=False)]
    pieces = []
    for k, material in enumerate(node.materials):
        chosen = faces[node.face_materials == k]
        if not len(chosen):
            continue
        used, local = _compact(chosen, len(vertices))
        pieces.append(trimesh.Trimesh(vertices=vertices[used], faces=local,
                                      vertex_normals=normals[used],
                                      visual=looks.visual(material), process=False))
    return pieces


def _compact(faces: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The vertices (of ``count``) that ``faces`` use, ascending, and the faces renumbered
    to them: :func:`numpy.unique` with its inverse, without its sort."""
    used = np.zeros(count, dtype=bool)
    used[faces] = True
    renumbered = np.cumsum(used) - 1
    return np.flatnonzero(used), renumbered[faces]


class _Looks:
    """The glTF metallic-roughness material of each :class:`Material`, made once per file
    and shared by every primitive that wears it (trimesh writes equal materials once)."""

    def __init__(self) -> None:
        self._made: dict[Material, Any] = {}

    def visual(self, material: Material) -> Any:
        """A trimesh visual carrying ``material``."""
        import trimesh
        from trimesh.visual.material import PBRMaterial

        pbr = self._made.get(material)
        if pbr is None:
            pbr = self._made[material] = PBRMaterial(
                name=material.name, baseColorFactor=material.linear_rgba(),
                metallicFactor=material.metallic, roughnessFactor=material.roughness,
                alphaMode="BLEND" if material.transparent else None,
                doubleSided=material.transparent)
        return trimesh.visual.TextureVisuals(material=pbr)


def _vertex_normals(meshes: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
    """Unit normals of the vertices of each mesh ``(vertices, faces)``: trimesh's mean of
    the normals of the faces around each vertex weighted by their corner angles
    (Thürrner & Wüthrich 1998, :func:`trimesh.geometry.weighted_vertex_normals`).

    All meshes go through trimesh's functions at once, as one mesh of separate pieces:
    a vertex's sum runs over the faces of its own mesh in the same order as for that mesh
    alone (and every other step works face by face or vertex by vertex), so each mesh
    gets the very normals it would get alone, for one sparse product instead of one per
    mesh and no trimesh object, whose caching costs more than the sums.

    A vertex whose mean has (nearly) zero length takes the normal of one of its faces
    that has one (else +y). A vertex where faces facing opposite ways meet (a stair's
    tread edge on its landing) averages to nothing, and one of only degenerate
    (zero-area) triangles has no normal at all, which glTF forbids (the Khronos
    validator's ACCESSOR_VECTOR3_NON_UNIT)."""
    from trimesh import geometry, triangles

    counts = [len(vertices) for vertices, _ in meshes]
    starts = np.cumsum([0, *counts])
    face_starts = np.cumsum([0, *(len(np.reshape(f, (-1, 3))) for _, f in meshes)])
    vertices = np.concatenate([np.zeros((0, 3)), *(v for v, _ in meshes)])
    faces = np.concatenate([np.zeros((0, 3), dtype=np.int64),
                            *(np.reshape(f, (-1, 3)) + start
                              for (_, f), start in zip(meshes, starts))])
    normals = np.zeros((len(vertices), 3))
    if len(faces):
        corners = vertices[faces]
        unit, valid = triangles.normals(triangles=corners, crosses=triangles.cross(corners))
        face_normals = unit
        if not valid.all():  # degenerate triangles: zero normals, as trimesh pads them
            face_normals = np.zeros((len(faces), 3))
            face_normals[valid] = unit
        normals = geometry.weighted_vertex_normals(
            vertex_count=len(vertices), faces=faces, face_normals=face_normals,
            face_angles=triangles.angles(corners))
    out = [normals[a:b] for a, b in zip(starts[:-1], starts[1:])]
    for k, own in enumerate(out):
        flat = np.linalg.norm(own, axis=1) < 0.5
        if flat.any() and face_starts[k + 1] > face_starts[k]:
            own_faces = faces[face_starts[k]:face_starts[k + 1]] - starts[k]
            around = geometry.vertex_face_indices(
                len(own), own_faces, geometry.index_sparse(len(own), own_faces))[flat]
            candidates = np.vstack([face_normals[face_starts[k]:face_starts[k + 1]],
                                    [[0.0, 0.0, 0.0]]])[around]  # -1 picks the zero row
            usable = np.linalg.norm(candidates, axis=2) > 0.5
            chosen = candidates[np.arange(len(around)), np.argmax(usable, axis=1)]
            chosen[~usable.any(axis=1)] = (0.0, 1.0, 0.0)
            own[flat] = chosen
    return out


def _mesh_key(meshes: Sequence[Any]) -> str:
    """A digest of the primitives of a glTF mesh: their vertices, faces and colours
    (vertex colours, or their material's name and base colour)."""
    digest = hashlib.sha1()
    for mesh in meshes:
        digest.update(np.ascontiguousarray(mesh.vertices, dtype=np.float64).tobytes())
        digest.update(np.ascontiguousarray(mesh.faces, dtype=np.int64).tobytes())
        visual = mesh.visual
        if visual.kind == "vertex":
            digest.update(np.ascontiguousarray(visual.vertex_colors).tobytes())
        else:
            material = visual.material
            base = getattr(material, "baseColorFactor", None)
            digest.update(repr((getattr(material, "name", None),
                                None if base is None else (str(np.asarray(base).dtype),
                                                          np.asarray(base).tolist()))
                               ).encode())
    return digest.hexdigest()


def _group_extras(scene: Scene) -> dict[str, dict[str, Any]]:
    """The facts of the floor and room group nodes, by group path."""
    out: dict[str, dict[str, Any]] = {}
    for plan in scene.floors:
        out[f"floor{plan.index}"] = {"kind": "floor", "floor": plan.index,
                                     "elevation": plan.elevation, "height": plan.height,
                                     "walking_surface": plan.floor_y}
        for room in plan.rooms:
            out[f"floor{plan.index}/{room.label}"] = _room_extras(plan, room.id)
    return out


def _room_extras(plan: FloorPlan, room_id: int) -> dict[str, Any]:
    room = plan.room(room_id)
    return {"kind": "room", "floor": plan.index, "room": room.id, "type": room.type,
            "area": room.area, "circulation": room.circulation}


def scene_as_glb(scene: Scene, nodes: Sequence[SceneNode]) -> bytes:
    """The scene's nodes as a binary glTF document with a node tree (module notes).

    Raises
    ------
    ExportError
        Two nodes share a path, or a node's extras cannot be stored as JSON.
    """
    import trimesh

    root = scene.name
    # the base frame has one child, the building node, so it is not written: the glTF
    # scene's one root is the building
    tm_scene = trimesh.Scene(base_frame="world")
    tm_scene.graph.update(frame_from="world", frame_to=root, matrix=np.eye(4),
                          metadata=json_safe({"kind": "building", "name": scene.name,
                                              "seed": scene.seed}))
    groups = _group_extras(scene)
    made: set[str] = set()
    seen: set[str] = set()
    meshes: dict[str, str] = {}  # mesh digest (_mesh_key) → geometry name
    made_from: dict[tuple[bytes, tuple[Material, ...]], str] = {}  # _source_key → name
    looks = _Looks()
    instances = instance_ids(nodes)
    names = class_names()
    pivots = [node_pivot(node) for node in nodes]
    local = [_local_vertices(node, inverse)
             for node, inverse in zip(nodes, _local_transforms(pivots))]
    sources = [_source_key(node, vertices) for node, vertices in zip(nodes, local)]
    first: dict[tuple[bytes, tuple[Material, ...]], int] = {}
    meshed = [i for i, source in enumerate(sources)
              if source is None or first.setdefault(source, i) == i]
    normals = dict(zip(meshed, _vertex_normals(
        [(local[i], np.asarray(nodes[i].mesh.faces, dtype=np.int64)) for i in meshed])))
    for i, node in enumerate(nodes):
        if node.path in seen or node.path in (root, "world"):
            raise ExportError(f"two scene nodes are both named {node.path!r}")
        seen.add(node.path)
        try:
            cid = node_class(node)
            extras = json_safe({**node.labels, "kind": node.kind, "static": node.static,
                                "class_id": cid, "class": names[cid],
                                "instance_id": instances[node.path]})
        except TypeError as error:
            raise ExportError(f"node {node.path!r}: {error}") from None
        parent = _parent(tm_scene, node.path, root, groups, made)
        source = sources[i]
        name = made_from.get(source) if source is not None else None
        if name is None:
            pieces = _local_meshes(node, local[i], normals[i], looks)
            key = _mesh_key(pieces)
            if key not in meshes:
                base = node.item.model if node.item is not None else node.path
                meshes[key] = base if base not in tm_scene.geometry else f"{base}#{len(meshes)}"
                tm_scene.geometry[meshes[key]] = pieces[0]
                for k, piece in enumerate(pieces[1:], start=1):
                    tm_scene.geometry[f"{meshes[key]}{_PRIMITIVE}{k}"] = piece
            name = meshes[key]
            if source is not None:
                made_from[source] = name
        tm_scene.graph.update(frame_from=parent, frame_to=node.path, matrix=pivots[i],
                              geometry=name, metadata=extras)
        made.add(node.path)
    lights = _add_lights(tm_scene, scene, root, groups, made)
    tm_scene.metadata.update(json_safe({"generator": "cga", "name": scene.name,
                                        "seed": scene.seed, "units": "metres", "up": "y"}))
    return tm_scene.export(file_type="glb", include_normals=True, unitize_normals=True,
                           tree_postprocessor=lambda tree: _finish_tree(tree, lights))


_PRIMITIVE = "@"
"""Joins a mesh's name and the number of its further primitive: trimesh writes one glTF
mesh per geometry, so a node's further materials are geometries ``<mesh>@1``, ... that
:func:`_finish_tree` moves into the node's mesh as primitives."""


def _add_lights(tm_scene: Any, scene: Scene, root: str, groups: Mapping[str, dict[str, Any]],
                made: set[str]) -> list[dict[str, Any]]:
    """A node per ceiling light (``floor0/room3_Office/light0``) under its room, pointing
    at its ``KHR_lights_punctual`` light; returns the lights' definitions."""
    out = []
    for k, light in enumerate(scene.lights):
        parent = _parent(tm_scene, light.name, root, groups, made)
        matrix = np.eye(4)
        matrix[:3, 3] = light.position
        extras = json_safe({"kind": "light", "floor": light.floor, "room": light.room,
                            "lumens": light.lumens, "temperature": light.temperature})
        extras["gltf_extensions"] = {"KHR_lights_punctual": {"light": k}}
        tm_scene.graph.update(frame_from=parent, frame_to=light.name, matrix=matrix,
                              metadata=extras)
        out.append({"name": light.name, "type": "point", "color": list(light.color),
                    "intensity": round(light.intensity, 6)})
    return out


def _finish_tree(tree: dict[str, Any], lights: list[dict[str, Any]]) -> None:
    """Join each node's further primitives into its mesh (see :data:`_PRIMITIVE`) and
    declare the lights (glTF ``KHR_lights_punctual``)."""
    meshes = tree.get("meshes", [])
    index = {m.get("name"): k for k, m in enumerate(meshes)}
    moved: dict[int, int] = {}
    for k, mesh in enumerate(meshes):
        name = str(mesh.get("name", ""))
        head, sep, tail = name.rpartition(_PRIMITIVE)
        if sep and tail.isdigit() and head in index:
            meshes[index[head]]["primitives"].extend(mesh["primitives"])
            moved[k] = index[head]
    if moved:
        kept = [k for k in range(len(meshes)) if k not in moved]
        new = {old: new for new, old in enumerate(kept)}
        tree["meshes"] = [meshes[k] for k in kept]
        for node in tree.get("nodes", []):
            if "mesh" in node:
                node["mesh"] = new[node["mesh"]]
    if lights:
        tree.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": lights}
        used = set(tree.get("extensionsUsed", [])) | {"KHR_lights_punctual"}
        tree["extensionsUsed"] = sorted(used)


def _parent(tm_scene: Any, path: str, root: str, groups: Mapping[str, dict[str, Any]],
            made: set[str]) -> str:
    """The group node above ``path``, made (with its own ancestors) when missing.

    ``made`` holds the groups made so far: asking trimesh's graph for its nodes instead
    re-hashes every transform after each update, quadratic in the scene's nodes (a
    300 m lot's glb took minutes)."""
    parent = root
    parts = path.split("/")
    for depth in range(1, len(parts)):
        group = "/".join(parts[:depth])
        if group not in made:
            made.add(group)
            extras = groups.get(group, {"kind": "group"})
            tm_scene.graph.update(frame_from=parent, frame_to=group, matrix=np.eye(4),
                                  metadata=json_safe(extras))
        parent = group
    return parent


def export_glb(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<out_dir>/<name>.glb`` atomically; returns ``[path]``."""
    return [atomic_write(Path(out_dir) / f"{name}.glb", scene_as_glb(scene, nodes))]
