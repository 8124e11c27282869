"""Wavefront OBJ output: ``<name>.obj`` with one group per scene node, and ``<name>.mtl``.

The OBJ is in the world frame (metres, y up), like the glTF. Each node becomes a group
named by its semantic path (``g floor0/room1_Livingroom/furniture/sofa``) using a
material per node kind (walls, slabs, ...) or per furniture model when the item has
colours of its own; meshes with vertex colours keep them (``v x y z r g b``). The writer
is hand-made on purpose: trimesh's OBJ export merges a scene into one mesh and loses the
node names this format is asked for.

:func:`obj_text` and :func:`mtl_text` are reused by the robot exporters for their mesh
files (in the ROS frame).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .palette import RGB, node_color

__all__ = ["MeshGroup", "obj_text", "mtl_text", "vertex_colors", "node_material", "node_groups",
           "export_obj"]


@dataclass(frozen=True)
class MeshGroup:
    """One OBJ group: a name, a triangle mesh (``vertices`` (n, 3), ``faces`` (m, 3)),
    the name of its material and optional per-vertex colours (n, 3) in 0..1."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    material: str
    colors: np.ndarray | None = None


def _safe(name: str) -> str:
    """OBJ names end at whitespace; keep everything else (slashes name the hierarchy)."""
    return re.sub(r"\s+", "_", name.strip()) or "unnamed"


def _format_rows(prefix: str, rows: np.ndarray, spec: str) -> str:
    return "".join(f"{prefix} {' '.join(format(v, spec) for v in row)}\n" for row in rows)


def obj_text(groups: Sequence[MeshGroup], *, mtl_file: str | None, header: str) -> str:
    """The OBJ text of ``groups`` (vertices with 6 decimals, 1-based triangle faces).

    Parameters
    ----------
    groups:
        Meshes to write, one ``g`` group each, in order.
    mtl_file:
        Name of the material library to reference (``mtllib``), or None for none.
    header:
        A comment line saying what the file is and in which frame.
    """
    lines = [f"# {header}\n"]
    if mtl_file is not None:
        lines.append(f"mtllib {mtl_file}\n")
    offset = 1
    for group in groups:
        vertices = np.asarray(group.vertices, dtype=float) + 0.0
        faces = np.asarray(group.faces, dtype=np.int64)
        lines.append(f"g {_safe(group.name)}\n")
        if mtl_file is not None:
            lines.append(f"usemtl {_safe(group.material)}\n")
        rows = np.round(vertices, 6) + 0.0
        if group.colors is not None:  # the common "v x y z r g b" extension
            rows = np.hstack([rows, np.round(np.asarray(group.colors, dtype=float), 4)])
        lines.append(_format_rows("v", rows, ".6f"))
        lines.append(_format_rows("f", faces + offset, "d"))
        offset += len(vertices)
    return "".join(lines)


def mtl_text(materials: Mapping[str, RGB]) -> str:
    """An MTL library with one diffuse colour per material name (sorted)."""
    blocks = ["# cga materials: diffuse colours, sRGB 0..1\n"]
    for name in sorted(materials):
        r, g, b = materials[name]
        blocks.append(f"\nnewmtl {_safe(name)}\nKa 0 0 0\nKd {r:.4f} {g:.4f} {b:.4f}\n"
                      f"Ks 0.05 0.05 0.05\nNs 10\nd 1\nillum 2\n")
    return "".join(blocks)


def vertex_colors(mesh: Any) -> np.ndarray | None:
    """A mesh's per-vertex colours as (n, 3) floats in 0..1, or None if it has none."""
    visual = getattr(mesh, "visual", None)
    if visual is None or visual.kind != "vertex":
        return None
    return np.asarray(visual.vertex_colors, dtype=float)[:, :3] / 255.0


def node_material(node: SceneNode) -> tuple[str, RGB]:
    """A node's material, returned as ``(name, colour)``: a furniture item with its own
    colours (the mean of its vertex colours) gets one per model, everything else one per
    node kind (:func:`cga.export.palette.node_color`)."""
    colors = vertex_colors(node.mesh)
    if node.kind == "furniture" and colors is not None:
        r, g, b = (float(c) for c in colors.mean(axis=0))
        model = node.item.model if node.item is not None else "item"
        return _safe(f"furniture_{model}"), (r, g, b)
    return _safe(node.kind), node_color(node.kind)


def node_groups(nodes: Sequence[SceneNode], transform: np.ndarray | None = None
                ) -> tuple[list[MeshGroup], dict[str, RGB]]:
    """OBJ groups and their materials for ``nodes``.

    Parameters
    ----------
    nodes:
        Scene nodes; empty meshes are skipped.
    transform:
        Optional 3×3 matrix applied to every vertex (e.g. world → ROS), or None.

    Returns
    -------
    (groups, materials)
        One group per node named by its path; material name → colour.
    """
    groups, materials = [], {}
    for node in nodes:
        vertices = np.asarray(node.mesh.vertices, dtype=float)
        faces = np.asarray(node.mesh.faces, dtype=np.int64)
        if len(faces) == 0:
            continue
        if transform is not None:
            vertices = vertices @ np.asarray(transform).T
        material, color = node_material(node)
        materials[material] = color
        groups.append(MeshGroup(node.path, vertices, faces, material, vertex_colors(node.mesh)))
    return groups, materials


def export_obj(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<name>.obj`` (world frame, y up, metres) and ``<name>.mtl``."""
    groups, materials = node_groups(nodes)
    header = (f"cga scene '{scene.name}' seed {scene.seed}: world frame, metres, y up; "
              f"one group per scene node")
    out = Path(out_dir)
    return [
        atomic_write(out / f"{name}.obj", obj_text(groups, mtl_file=f"{name}.mtl", header=header)),
        atomic_write(out / f"{name}.mtl", mtl_text(materials)),
    ]
