"""Wavefront OBJ output: ``<name>.obj`` with one group per scene node, and ``<name>.mtl``.

The OBJ is in the world frame (metres, y up), like the glTF. Each node becomes a group
named by its semantic path (``g floor0/room1_Livingroom/furniture/sofa``), one run of
faces per material of the node (:mod:`cga.appearance`: the same materials as the glb;
``usemtl``), the MTL giving each material's colour, opacity and the PBR extension's
roughness and metalness; meshes with vertex colours keep them (``v x y z r g b``). The writer
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
from cga.mesh import TriangleMesh
from cga.scene import Scene, SceneNode

from cga.appearance.material import Material

from .palette import node_materials

__all__ = ["MeshGroup", "obj_text", "mtl_text", "vertex_colors", "mesh_groups", "node_groups",
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
        Meshes to write, in order: one ``g`` group each, a group that follows one of
        the same name (another material of a node) continuing it.
    mtl_file:
        Name of the material library to reference (``mtllib``), or None for none.
    header:
        A comment line saying what the file is and in which frame.
    """
    lines = [f"# {header}\n"]
    if mtl_file is not None:
        lines.append(f"mtllib {mtl_file}\n")
    offset = 1
    previous = None
    for group in groups:
        vertices = np.asarray(group.vertices, dtype=float) + 0.0
        faces = np.asarray(group.faces, dtype=np.int64)
        if group.name != previous:  # a node's materials follow one another in its group
            lines.append(f"g {_safe(group.name)}\n")
            previous = group.name
        if mtl_file is not None:
            lines.append(f"usemtl {_safe(group.material)}\n")
        rows = np.round(vertices, 6) + 0.0
        if group.colors is not None:  # the common "v x y z r g b" extension
            rows = np.hstack([rows, np.round(np.asarray(group.colors, dtype=float), 4)])
        lines.append(_format_rows("v", rows, ".6f"))
        lines.append(_format_rows("f", faces + offset, "d"))
        offset += len(vertices)
    return "".join(lines)


def mtl_text(materials: Mapping[str, Material]) -> str:
    """An MTL library with one material per name (sorted): diffuse colour (sRGB), ``d``
    (opacity) and the PBR extension's ``Pr`` (roughness) and ``Pm`` (metallic)."""
    blocks = ["# cga materials: diffuse colours sRGB 0..1; Pr roughness, Pm metallic\n"]
    for name in sorted(materials):
        m = materials[name]
        r, g, b = m.color
        shininess = round(2.0 + 98.0 * (1.0 - m.roughness) ** 2, 1)
        blocks.append(f"\nnewmtl {_safe(name)}\nKa 0 0 0\nKd {r:.4f} {g:.4f} {b:.4f}\n"
                      f"Ks 0.05 0.05 0.05\nNs {shininess:g}\nd {m.alpha:g}\n"
                      f"Pr {m.roughness:g}\nPm {m.metallic:g}\nillum 2\n")
    return "".join(blocks)


def vertex_colors(mesh: Any) -> np.ndarray | None:
    """A mesh's per-vertex colours as (n, 3) floats in 0..1, or None if it has none: a
    :class:`~cga.mesh.TriangleMesh`'s own (no trimesh made), a trimesh's visual's."""
    if isinstance(mesh, TriangleMesh):
        colors = mesh.vertex_colors
        return None if colors is None else np.asarray(colors, dtype=float)[:, :3] / 255.0
    visual = getattr(mesh, "visual", None)
    if visual is None or visual.kind != "vertex":
        return None
    return np.asarray(visual.vertex_colors, dtype=float)[:, :3] / 255.0


def mesh_groups(node: SceneNode, name: str, vertices: np.ndarray | None = None
                ) -> tuple[list[MeshGroup], dict[str, Material]]:
    """A node's mesh as one group per material (:func:`cga.export.palette.node_materials`),
    each with the vertices its triangles use, all named ``name``; and those materials by
    name.

    Parameters
    ----------
    node:
        The scene node.
    name:
        The groups' name.
    vertices:
        The node's vertices in the frame to write (default: the node's own, world frame).
    """
    points = np.asarray(node.mesh.vertices if vertices is None else vertices, dtype=float)
    faces = np.asarray(node.mesh.faces, dtype=np.int64)
    colors = vertex_colors(node.mesh)
    materials, index = node_materials(node)
    groups, used = [], {}
    for k, material in enumerate(materials):
        chosen = faces[index == k]
        if not len(chosen):
            continue
        keep, local = np.unique(chosen, return_inverse=True)
        groups.append(MeshGroup(name, points[keep], local.reshape(-1, 3), material.name,
                                colors[keep] if colors is not None else None))
        used[material.name] = material
    return groups, used


def node_groups(nodes: Sequence[SceneNode], transform: np.ndarray | None = None
                ) -> tuple[list[MeshGroup], dict[str, Material]]:
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
        Groups named by their node's path (one per material of the node, so a group
        name repeats); material name → material.
    """
    groups: list[MeshGroup] = []
    materials: dict[str, Material] = {}
    for node in nodes:
        if len(node.mesh.faces) == 0:
            continue
        vertices = np.asarray(node.mesh.vertices, dtype=float)
        if transform is not None:
            vertices = vertices @ np.asarray(transform).T
        parts, used = mesh_groups(node, node.path, vertices)
        groups.extend(parts)
        materials.update(used)
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
