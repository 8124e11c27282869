"""``<name>.glb``: the building as binary glTF 2.0 (DESIGN §10).

One glTF node per :class:`~cga.scene.SceneNode`, named by its path
(``floor1/room3_Kitchen/wall2``, ``Lot/Body/Upper[2]``), y up, metres, world
coordinates baked into the vertices (no node transforms). A node's ``extras`` are the
SceneNode's extras plus its ``kind`` and ``static`` flag, so viewers and loaders get the
semantics. Meshes that carry no colour of their own get a material of their kind's
colour (:func:`cga.export.palette.node_color`).

The bytes are a pure function of the scene: nodes in the given order, no timestamps,
extras with sorted keys. The same seed gives a byte-identical file (tested).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .palette import node_color

__all__ = ["scene_as_glb", "export_glb", "json_safe"]


def json_safe(value: Any) -> Any:
    """``value`` as plain JSON data: numpy scalars/arrays → numbers/lists, tuples → lists,
    mappings with sorted string keys, sets as sorted lists.

    Raises
    ------
    TypeError
        A value with no JSON form (the message names its type).
    """
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


def _export_mesh(node: SceneNode) -> Any:
    """A copy of the node's mesh without metadata (which trimesh would write as mesh
    extras), coloured by kind when it has no colours of its own."""
    import trimesh
    from trimesh.visual.material import PBRMaterial

    source = node.mesh
    visual = source.visual
    if visual.kind is None:
        r, g, b = node_color(node.kind)
        material = PBRMaterial(name=node.kind, baseColorFactor=[r, g, b, 1.0],
                               metallicFactor=0.0, roughnessFactor=0.9)
        visual = trimesh.visual.TextureVisuals(material=material)
    else:
        visual = visual.copy()
    return trimesh.Trimesh(vertices=np.asarray(source.vertices, dtype=float),
                           faces=np.asarray(source.faces), visual=visual, process=False)


def scene_as_glb(scene: Scene, nodes: Sequence[SceneNode]) -> bytes:
    """The scene's nodes as a binary glTF document.

    Raises
    ------
    ExportError
        Two nodes share a path, or a node's extras cannot be stored as JSON.
    """
    import trimesh

    tm_scene = trimesh.Scene()
    seen: set[str] = set()
    for node in nodes:
        if node.path in seen:
            raise ExportError(f"two scene nodes are both named {node.path!r}")
        seen.add(node.path)
        try:
            extras = json_safe({**node.labels, "kind": node.kind, "static": node.static})
        except TypeError as error:
            raise ExportError(f"node {node.path!r}: {error}") from None
        tm_scene.add_geometry(_export_mesh(node), node_name=node.path, geom_name=node.path,
                              metadata=extras)
    tm_scene.metadata.update(json_safe({"generator": "cga", "name": scene.name,
                                        "seed": scene.seed, "units": "metres", "up": "y"}))
    return tm_scene.export(file_type="glb")


def export_glb(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<out_dir>/<name>.glb`` atomically; returns ``[path]``."""
    return [atomic_write(Path(out_dir) / f"{name}.glb", scene_as_glb(scene, nodes))]
