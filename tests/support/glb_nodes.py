"""glTF nodes of a cga glb as the file states them, independent of cga's reader.

A node whose mesh has several primitives (one per material) is one glTF node, but
trimesh loads each primitive as a child frame of its own; the tests ask about nodes.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

import trimesh

__all__ = ["gltf_document", "mesh_node_names", "node_mesh"]


def gltf_document(path: Path) -> dict:
    """The JSON chunk of a binary glTF file (glTF 2.0 §4.4: header, then the JSON chunk)."""
    data = path.read_bytes()
    magic, _version, _length = struct.unpack_from("<III", data, 0)
    assert magic == 0x46546C67, "not a binary glTF file"
    chunk_length, chunk_type = struct.unpack_from("<II", data, 12)
    assert chunk_type == 0x4E4F534A, "the first chunk is not JSON"
    return json.loads(data[20:20 + chunk_length])


def mesh_node_names(path: Path) -> set[str]:
    """Names of the glTF nodes that carry a mesh."""
    return {node["name"] for node in gltf_document(path).get("nodes", []) if "mesh" in node}


def node_mesh(scene: trimesh.Scene, name: str) -> trimesh.Trimesh:
    """A node's primitives, joined, in world coordinates, from a scene trimesh loaded."""
    frames = [name] if name in scene.graph.nodes_geometry else [
        frame for frame in scene.graph.nodes_geometry
        if scene.graph.transforms.parents.get(frame) == name]
    assert frames, f"no mesh under node {name!r}"
    parts = []
    for frame in frames:
        matrix, geometry = scene.graph[frame]
        parts.append(scene.geometry[geometry].copy().apply_transform(matrix))
    return trimesh.util.concatenate(parts)
