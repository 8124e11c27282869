"""The glb writer writes the file trimesh's glTF exporter wrote, without importing trimesh.

cga once built a :class:`trimesh.Scene` and let trimesh write it; :func:`trimesh_glb`
below still does, from the same nodes, and the files are compared byte for byte (with
trimesh's ``asset.generator``, the one string that differs). The vertex normals are
compared bit for bit with trimesh's own functions.
"""

from __future__ import annotations

import hashlib
import json
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
import trimesh
from trimesh import geometry, triangles
from trimesh.visual.material import PBRMaterial

import cga.export.glb as glb
from cga.export.palette import kind_material
from cga.mesh import TriangleMesh
from cga.pipeline import build
from cga.scene import Scene, SceneNode
from cga.semantics import class_names, instance_ids, node_class

DEMOS = Path(__file__).resolve().parents[3] / "demos"
TRIMESH = "https://github.com/mikedh/trimesh"


def local_vertices(node, inverse):
    """The node's vertices in its pivot's frame (``inverse``, None: the identity) on a
    micrometre grid, the node alone."""
    vertices = np.asarray(node.mesh.vertices, dtype=float)
    if inverse is not None:
        vertices = vertices @ inverse[:3, :3].T + inverse[:3, 3]
    return np.round(vertices, 6) + 0.0


def trimesh_normals(meshes):
    """The vertex normals as the writer computed them with trimesh's functions: trimesh's
    angle-weighted mean (over all meshes at once), and where that has no length the normal
    of the first face with one among those ``vertex_face_indices`` lists, else +y."""
    counts = [len(vertices) for vertices, _ in meshes]
    starts = np.cumsum([0, *counts])
    face_starts = np.cumsum([0, *(len(np.reshape(f, (-1, 3))) for _, f in meshes)])
    vertices = np.concatenate([np.zeros((0, 3)), *(v for v, _ in meshes)])
    faces = np.concatenate([np.zeros((0, 3), dtype=np.int64),
                            *(np.reshape(f, (-1, 3)) + start
                              for (_, f), start in zip(meshes, starts))])
    normals = np.zeros((len(vertices), 3))
    face_normals = np.zeros((len(faces), 3))
    if len(faces):
        corners = vertices[faces]
        unit, valid = triangles.normals(triangles=corners, crosses=triangles.cross(corners))
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


def trimesh_glb(scene: Scene, nodes) -> bytes:
    """The glb trimesh's exporter writes for the nodes: the same node tree, extras and
    lights in a trimesh scene, one geometry per material of a node (joined into the node's
    mesh afterwards), each distinct mesh once, the normals of :func:`trimesh_normals`."""
    root = scene.name
    tm = trimesh.Scene(base_frame="world")
    tm.graph.update(frame_from="world", frame_to=root, matrix=np.eye(4),
                    metadata=glb.json_safe({"kind": "building", "name": root,
                                            "seed": scene.seed}))
    groups = glb._group_extras(scene)
    made = set()

    def parent(path):
        above = root
        parts = path.split("/")
        for depth in range(1, len(parts)):
            group = "/".join(parts[:depth])
            if group not in made:
                made.add(group)
                tm.graph.update(frame_from=above, frame_to=group, matrix=np.eye(4),
                                metadata=glb.json_safe(groups.get(group, {"kind": "group"})))
            above = group
        return above

    looks = {}

    def look(material):
        if material not in looks:
            looks[material] = PBRMaterial(
                name=material.name, baseColorFactor=material.linear_rgba(),
                metallicFactor=material.metallic, roughnessFactor=material.roughness,
                alphaMode="BLEND" if material.transparent else None,
                doubleSided=material.transparent)
        return trimesh.visual.TextureVisuals(material=looks[material])

    pivots = [glb.node_pivot(node) for node in nodes]
    local = [local_vertices(node, inverse)
             for node, inverse in zip(nodes, glb._local_transforms(pivots))]
    normals = trimesh_normals([(v, np.asarray(n.mesh.faces, dtype=np.int64))
                               for v, n in zip(local, nodes)])
    instances, names, meshes = instance_ids(nodes), class_names(), {}
    for node, pivot, vertices, own in zip(nodes, pivots, local, normals):
        faces = np.asarray(node.mesh.faces, dtype=np.int64)
        if node.materials:
            pieces = []
            for k, material in enumerate(node.materials):
                chosen = faces[node.face_materials == k]
                if len(chosen):
                    used, renumbered = np.unique(chosen, return_inverse=True)
                    pieces.append(trimesh.Trimesh(
                        vertices=vertices[used], faces=renumbered.reshape(-1, 3),
                        vertex_normals=own[used], visual=look(material), process=False))
        else:
            visual = node.mesh.visual
            visual = look(kind_material(node.kind)) if visual.kind is None else visual.copy()
            pieces = [trimesh.Trimesh(vertices=vertices, faces=faces, vertex_normals=own,
                                      visual=visual, process=False)]
        key = hashlib.sha1()
        for piece in pieces:
            key.update(piece.vertices.tobytes() + piece.faces.tobytes())
            key.update(piece.visual.vertex_colors.tobytes() if piece.visual.kind == "vertex"
                       else piece.visual.material.name.encode())
        if key.digest() not in meshes:
            base = node.item.model if node.item is not None else node.path
            name = base if base not in tm.geometry else f"{base}#{len(meshes)}"
            meshes[key.digest()] = name
            for k, piece in enumerate(pieces):
                tm.geometry[f"{name}@{k}" if k else name] = piece
        cid = node_class(node)
        tm.graph.update(frame_from=parent(node.path), frame_to=node.path, matrix=pivot,
                        geometry=meshes[key.digest()], metadata=glb.json_safe(
                            {**node.labels, "kind": node.kind, "static": node.static,
                             "class_id": cid, "class": names[cid],
                             "instance_id": instances[node.path]}))
        made.add(node.path)
    lights = []
    for k, light in enumerate(scene.lights):
        matrix = np.eye(4)
        matrix[:3, 3] = light.position
        extras = glb.json_safe({"kind": "light", "floor": light.floor, "room": light.room,
                                "lumens": light.lumens, "temperature": light.temperature})
        extras["gltf_extensions"] = {"KHR_lights_punctual": {"light": k}}
        tm.graph.update(frame_from=parent(light.name), frame_to=light.name, matrix=matrix,
                        metadata=extras)
        lights.append({"name": light.name, "type": "point", "color": list(light.color),
                       "intensity": round(light.intensity, 6)})
    tm.metadata.update(glb.json_safe({"generator": "cga", "name": root, "seed": scene.seed,
                                      "units": "metres", "up": "y"}))

    def finish(tree):
        # each "<mesh>@<k>" geometry's primitive joins <mesh>; the lights are declared
        index = {mesh["name"]: k for k, mesh in enumerate(tree["meshes"])}
        kept = []
        for k, mesh in enumerate(tree["meshes"]):
            head, _, tail = mesh["name"].rpartition("@")
            if tail.isdigit() and head in index:
                tree["meshes"][index[head]]["primitives"] += mesh["primitives"]
            else:
                kept.append(k)
        renumbered = {old: new for new, old in enumerate(kept)}
        tree["meshes"] = [tree["meshes"][k] for k in kept]
        for node in tree["nodes"]:
            if "mesh" in node:
                node["mesh"] = renumbered[node["mesh"]]
        if lights:
            tree["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
            tree["extensionsUsed"] = sorted({*tree["extensionsUsed"], "KHR_lights_punctual"})

    return tm.export(file_type="glb", include_normals=True, unitize_normals=True,
                     tree_postprocessor=finish)


def document(data: bytes) -> dict:
    length, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON"
    return json.loads(data[20:20 + length])


@pytest.fixture(scope="module")
def built():
    return {name: build(DEMOS / f"{name}.grammar", seed=seed, formats=[], physics=False,
                        quiet=True) for name, seed in (("house", 3), ("massing", 0))}


@pytest.mark.parametrize("name", ["house", "massing"])
def test_a_build_s_file_is_the_one_trimesh_writes_but_for_the_generator(built, name,
                                                                       monkeypatch):
    scene = built[name]
    expected = trimesh_glb(scene, scene.nodes)
    written = glb.scene_as_glb(scene, scene.nodes)
    ours, theirs = document(written), document(expected)
    assert (ours["asset"], theirs["asset"]) == ({"version": "2.0", "generator": "cga"},
                                                {"version": "2.0", "generator": TRIMESH})
    assert written.endswith(expected[-theirs["buffers"][0]["byteLength"]:])
    monkeypatch.setattr(glb, "_GENERATOR", TRIMESH)
    assert glb.scene_as_glb(scene, scene.nodes) == expected


def test_undressed_nodes_are_written_as_trimesh_wrote_them(small_scene, monkeypatch):
    """Nodes without materials (hand-made scenes): their kind's material, or their own
    vertex colours (a trimesh object's, or a TriangleMesh's, read without trimesh)."""
    scene, nodes = small_scene
    coloured = nodes[0].mesh.copy()
    coloured.visual.vertex_colors = np.arange(len(coloured.vertices) * 4).reshape(-1, 4) % 256
    nodes = [SceneNode("painted/box", "mass", coloured), *nodes]
    monkeypatch.setattr(glb, "_GENERATOR", TRIMESH)
    expected = trimesh_glb(scene, nodes)
    assert glb.scene_as_glb(scene, nodes) == expected
    arrays = [SceneNode(n.path, n.kind, TriangleMesh(
        n.mesh.vertices, n.mesh.faces,
        n.mesh.visual.vertex_colors if n.mesh.visual.kind == "vertex" else None),
        n.extras, n.static, item=n.item, door=n.door) for n in nodes]
    monkeypatch.setitem(sys.modules, "trimesh", None)  # an import of trimesh fails
    assert glb.scene_as_glb(scene, arrays) == expected
    primitive = document(expected)["meshes"][0]["primitives"][0]
    assert "COLOR_0" in primitive["attributes"] and "material" not in primitive


def test_writing_a_build_s_glb_imports_no_trimesh():
    script = (
        "import sys\n"
        "from cga.pipeline import build\n"
        "from cga.export.glb import scene_as_glb\n"
        f"scene = build({str(DEMOS / 'house.grammar')!r}, seed=0, formats=[], physics=False,"
        " quiet=True)\n"
        "nodes = scene.nodes\n"
        "assert 'trimesh' not in sys.modules, 'the build imported trimesh'\n"
        "assert scene_as_glb(scene, nodes)[:4] == b'glTF'\n"
        "assert 'trimesh' not in sys.modules, 'writing the glb imported trimesh'\n")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=300, check=False)
    assert result.returncode == 0, result.stderr


def test_a_scene_without_meshes_has_no_bin_chunk():
    data = glb.scene_as_glb(Scene(name="t", seed=0, units=1.0, terminals=[]), [])
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    json_length, kind = struct.unpack_from("<I4s", data, 12)
    assert (magic, version, length, kind) == (b"glTF", 2, len(data), b"JSON")
    assert 20 + json_length == len(data)  # nothing after the JSON chunk
    assert document(data)["nodes"] == [{"name": "t", "extras": {"kind": "building", "name": "t",
                                                                "seed": 0}}]


def test_vertex_normals_of_a_build_are_trimesh_s_bit_for_bit(built):
    for scene in built.values():
        meshes = [(np.asarray(n.mesh.vertices, dtype=float),
                   np.asarray(n.mesh.faces, dtype=np.int64)) for n in scene.nodes]
        for ours, theirs in zip(glb._vertex_normals(meshes), trimesh_normals(meshes)):
            assert ours.tobytes() == theirs.tobytes()


MESH = st.integers(1, 12).flatmap(lambda n: st.tuples(
    # corners on a coarse grid, so triangles are often degenerate, coplanar or opposed
    st.lists(st.tuples(*[st.integers(-2, 2)] * 3), min_size=n, max_size=n),
    st.lists(st.tuples(*[st.integers(0, n - 1)] * 3), max_size=16),
    st.sampled_from([1.0, 0.1, 1e-7, 3.3])))


@settings(max_examples=300, deadline=None)
@given(st.lists(MESH, min_size=1, max_size=4))
def test_vertex_normals_are_trimesh_s_bit_for_bit(cases):
    meshes = [(np.array(v, dtype=float) * scale, np.array(f, dtype=np.int64).reshape(-1, 3))
              for v, f, scale in cases]
    for ours, theirs in zip(glb._vertex_normals(meshes), trimesh_normals(meshes)):
        assert ours.tobytes() == theirs.tobytes()
