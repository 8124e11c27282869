"""Colours shared by the exporters: room types on plans, materials in OBJ/URDF/SDF.

Common room types get fixed soft colours so plans of different builds read alike (a
kitchen is always the same yellow); any other type gets a colour derived from a hash
of its name, so it is stable across runs and machines. Scene nodes are coloured by
their materials (:mod:`cga.appearance`); undressed meshes by their own colours, else
by node kind.
"""

from __future__ import annotations

import colorsys
import hashlib
from typing import TYPE_CHECKING

import numpy as np

from cga.appearance.material import Material, linear_to_srgb
from cga.mesh import as_trimesh

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    from cga.scene import SceneNode

__all__ = [
    "RGB",
    "ROOM_COLORS",
    "UNTYPED_ROOM_COLOR",
    "KIND_COLORS",
    "room_color",
    "node_color",
    "face_colors",
    "node_face_colors",
    "kind_material",
    "node_materials",
    "hex_color",
]

RGB = tuple[float, float, float]
"""A colour as (r, g, b), each 0..1 (sRGB)."""


def _hex(code: str) -> RGB:
    return tuple(int(code[i:i + 2], 16) / 255.0 for i in (1, 3, 5))  # type: ignore[return-value]


ROOM_COLORS: dict[str, RGB] = {
    "livingroom": _hex("#f3dcb2"),
    "kitchen": _hex("#f7eba0"),
    "diningroom": _hex("#f4c6b4"),
    "bedroom": _hex("#c9dcf2"),
    "childroom": _hex("#d6cdf0"),
    "bathroom": _hex("#b8e3e0"),
    "toilet": _hex("#c4e6ec"),
    "laundryroom": _hex("#d3e8d0"),
    "storageroom": _hex("#dedbd2"),
    "office": _hex("#e3d3ea"),
    "corridor": _hex("#ece8e1"),
    "hall": _hex("#ece8e1"),
    "commonroom": _hex("#e6e2d6"),
}
"""Plan colours of common room types, keyed by lower-case type name."""

UNTYPED_ROOM_COLOR: RGB = _hex("#f2f2f0")
"""Plan colour of a room that has no type (``type_rooms`` did not run)."""

KIND_COLORS: dict[str, RGB] = {
    "wall": _hex("#e8e4dc"),
    "slab": _hex("#b9b2a6"),
    "ceiling": _hex("#f4f2ee"),
    "roof": _hex("#9c6b57"),
    "stair": _hex("#c9b79c"),
    "rail": _hex("#5d5d5d"),
    "furniture": _hex("#a8865f"),
    "mass": _hex("#d9d4ca"),
    "face": _hex("#cfc9bd"),
}
"""Mesh colours by :class:`cga.scene.SceneNode` kind."""

_OTHER_KIND_COLOR: RGB = _hex("#c8c8c8")


def room_color(room_type: str | None) -> RGB:
    """The plan colour of a room type (case-insensitive).

    Types in :data:`ROOM_COLORS` get their fixed colour; other names a pastel whose hue
    comes from the MD5 of the lower-case name (stable everywhere); ``None`` gets
    :data:`UNTYPED_ROOM_COLOR`.
    """
    if room_type is None:
        return UNTYPED_ROOM_COLOR
    key = room_type.lower()
    if key in ROOM_COLORS:
        return ROOM_COLORS[key]
    digest = hashlib.md5(key.encode("utf-8")).digest()
    hue = int.from_bytes(digest[:2], "big") / 65536.0
    return colorsys.hls_to_rgb(hue, 0.86, 0.55)


def node_color(kind: str) -> RGB:
    """The display colour of a scene node without colours of its own: its kind's."""
    return KIND_COLORS.get(kind, _OTHER_KIND_COLOR)


def face_colors(mesh: "trimesh.Trimesh", kind: str) -> np.ndarray:
    """``float[faces, 3]`` sRGB colour of every triangle: the mesh's own colours (vertex or
    face colours, e.g. of a furniture model; a material's base colour, e.g. read back from
    a glb), else its node kind's colour."""
    import trimesh

    visual = mesh.visual
    count = len(mesh.faces)
    if isinstance(visual, trimesh.visual.ColorVisuals) and visual.kind is not None:
        colors = np.asarray(visual.face_colors)
        if len(colors) == count:
            return colors[:, :3].astype(float) / 255.0
    material = getattr(visual, "material", None)
    base = getattr(material, "baseColorFactor", None)
    if base is not None and len(base) >= 3:
        rgb = np.asarray(base)[:3]  # trimesh keeps it as uint8; glTF writes 0..1 floats
        scale = 255.0 if np.issubdtype(rgb.dtype, np.integer) else 1.0
        # glTF's base colour is linear (cga.appearance.material)
        return np.tile(linear_to_srgb(rgb.astype(float) / scale), (count, 1))
    return np.tile(node_color(kind), (count, 1))


def kind_material(kind: str) -> Material:
    """The material of an undressed mesh: its kind's colour (:func:`node_color`)."""
    return Material.of(kind, kind, node_color(kind), 0.9, 0.0, 1.0)


def node_materials(node: "SceneNode") -> tuple[tuple[Material, ...], np.ndarray]:
    """A node's materials and the index into them of each triangle: its own
    (:attr:`SceneNode.materials`) when it is dressed; else one material, a furniture
    item's mean vertex colour or its kind's."""
    count = len(node.mesh.faces)
    if node.materials and node.face_materials is not None:
        return node.materials, np.asarray(node.face_materials)
    visual = getattr(node.mesh, "visual", None)
    if node.kind == "furniture" and visual is not None and visual.kind == "vertex":
        r, g, b = (float(c) for c in np.asarray(visual.vertex_colors, dtype=float)[:, :3].mean(
            axis=0) / 255.0)
        model = node.item.model if node.item is not None else "item"
        material = Material.of(f"furniture_{model}", "furniture", (r, g, b), 0.7, 0.0, 1.0)
    else:
        material = kind_material(node.kind)
    return (material,), np.zeros(count, dtype=np.int64)


def node_face_colors(node: "SceneNode") -> np.ndarray:
    """``float[faces, 3]`` sRGB colour of every triangle of a scene node: its materials'
    (:attr:`SceneNode.materials`) when it is dressed, else :func:`face_colors`."""
    if node.materials and node.face_materials is not None:
        colors = np.array([m.color for m in node.materials], dtype=float)
        return colors[node.face_materials]
    return face_colors(as_trimesh(node.mesh), node.kind)


def hex_color(color: RGB) -> str:
    """``#rrggbb`` for a colour (SVG, legends)."""
    return "#" + "".join(f"{round(max(0.0, min(1.0, c)) * 255):02x}" for c in color)
