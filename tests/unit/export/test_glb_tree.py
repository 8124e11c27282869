"""The glTF of a furnished build is a node tree with item pivots and shared meshes.

Checked on the JSON chunk of the GLB, read with the glTF 2.0 layout (not with the
exporter's code), and by loading it back with trimesh.
"""

from __future__ import annotations

import io
import json
import struct
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
import trimesh

from cga.export.glb import scene_as_glb
from cga.pipeline import build

HOUSE = Path(__file__).resolve().parents[3] / "demos" / "house.grammar"


@pytest.fixture(scope="module")
def glb():
    scene = build(HOUSE, seed=1, formats=[], physics=False, quiet=True)
    nodes = scene.nodes
    data = scene_as_glb(scene, nodes)
    length = struct.unpack("<I", data[12:16])[0]
    return scene, nodes, data, json.loads(data[20:20 + length])


def _parents(doc):
    return {child: i for i, node in enumerate(doc["nodes"]) for child in node.get("children", ())}


def test_tree_building_floor_room_item(glb):
    scene, nodes, _, doc = glb
    names = [n["name"] for n in doc["nodes"]]
    parents = _parents(doc)
    (root,) = doc["scenes"][0]["nodes"]
    assert names[root] == "house" and doc["nodes"][root]["extras"]["kind"] == "building"
    for node in nodes:
        index = names.index(node.path)
        chain = []
        while index in parents:
            index = parents[index]
            chain.append(names[index])
        # every ancestor is a prefix of the path, up to the building
        assert chain[-1] == "house"
        assert all(node.path.startswith(c + "/") for c in chain[:-1])
    for plan in scene.floors:
        floor = doc["nodes"][names.index(f"floor{plan.index}")]
        assert floor["extras"]["walking_surface"] == pytest.approx(plan.floor_y)
        for room in plan.rooms:
            extras = doc["nodes"][names.index(f"floor{plan.index}/{room.label}")]["extras"]
            assert extras["type"] == room.type and extras["area"] == pytest.approx(room.area)


def test_items_have_pivots_and_share_meshes_with_normals(glb):
    _, nodes, data, doc = glb
    names = [n["name"] for n in doc["nodes"]]
    items = [n for n in nodes if n.kind == "furniture"]
    gltf_items = [doc["nodes"][names.index(n.path)] for n in items]
    assert all("matrix" in g for g in gltf_items)
    # a pivot sits at the item: the node's translation lies in the item's bounding box
    # (a door's hinge within its 1 cm gaps of the leaf)
    for node, g in zip(items, gltf_items):
        translation = np.array(g["matrix"][12:15])
        lo, hi = node.mesh.bounds
        slack = 0.011 if node.door is not None else 1e-6
        assert np.all(translation >= lo - slack) and np.all(translation <= hi + slack), node.path
        assert g["extras"]["model"] == node.item.model
    meshes = {g["mesh"] for g in gltf_items}
    assert len(meshes) < len(gltf_items)  # instances of one model share a mesh
    assert all("NORMAL" in p["attributes"] for m in doc["meshes"] for p in m["primitives"])
    # loaded back, every mesh lands where the scene node is
    loaded = trimesh.load(io.BytesIO(data), file_type="glb")
    children = loaded.graph.transforms.children
    for node in items[:10]:
        # a mesh of several primitives (one per material) loads as one child frame each
        frames = [node.path] if loaded.graph[node.path][1] else children[node.path]
        placed = np.vstack([trimesh.transform_points(loaded.geometry[geometry].vertices,
                                                     transform)
                            for transform, geometry in (loaded.graph[f] for f in frames)])
        assert np.allclose([placed.min(axis=0), placed.max(axis=0)], node.mesh.bounds,
                           atol=1e-5), node.path


def test_a_mesh_shared_by_instances_is_made_once_and_writes_the_same_bytes(glb, monkeypatch):
    """The exporter makes each distinct mesh once (instances of a model at one size
    share it); making every node's mesh anew, as the exporter once did, writes the very
    same file."""
    import cga.export.glb as glb_module

    scene, nodes, data, doc = glb
    made = []
    original = glb_module._primitives
    monkeypatch.setattr(glb_module, "_primitives",
                        lambda node, *rest: made.append(node.path) or original(node, *rest))
    assert scene_as_glb(scene, nodes) == data
    items = [n for n in nodes if n.kind == "furniture"]
    assert len(made) < len(nodes) and len({n.item.model for n in items}) <= len(made)
    made.clear()
    monkeypatch.setattr(glb_module, "_source_key", lambda node, vertices: None)
    assert scene_as_glb(scene, nodes) == data
    assert len(made) == len(nodes)


def test_vertex_normals_are_trimesh_s_and_every_one_is_a_unit_vector(glb):
    """Normals computed for all meshes at once from the arrays are bit for bit those of a
    trimesh object of each mesh alone wherever those have length; elsewhere (a stair's
    tread edge, where opposite faces meet) they are the unit normal of one of the
    vertex's faces."""
    from cga.export.glb import _vertex_normals

    _, nodes, _, _ = glb
    meshes = [(np.asarray(n.mesh.vertices, dtype=float), np.asarray(n.mesh.faces, dtype=np.int64))
              for n in nodes]
    replaced = 0
    for node, (vertices, faces), normals in zip(nodes, meshes, _vertex_normals(meshes)):
        own = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
        expected = np.asarray(own.vertex_normals)
        kept = np.linalg.norm(expected, axis=1) >= 0.5
        assert np.array_equal(normals[kept], expected[kept]), node.path
        assert np.allclose(np.linalg.norm(normals, axis=1), 1.0), node.path
        for v in np.flatnonzero(~kept):
            around = own.face_normals[np.any(faces == v, axis=1)]
            assert np.any(np.all(np.isclose(around, normals[v]), axis=1)), node.path
        replaced += int((~kept).sum())
    assert replaced  # the house's stair has such vertices


def test_a_vertex_of_only_degenerate_triangles_points_up():
    from cga.export.glb import _vertex_normals

    vertices = np.array([[0, 0, 0], [0, 0, -1], [1, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0.0]])
    faces = np.array([[0, 1, 2], [3, 4, 5]])  # facing down; the second a line, no area
    # (a mesh without faces has no normals; a vertex no face uses points up)
    empty = (np.zeros((2, 3)), np.zeros((0, 3), dtype=np.int64))
    normals = _vertex_normals([empty, (vertices, faces), (vertices, faces[:1])])
    assert np.array_equal(normals[0], np.zeros((2, 3)))
    assert np.allclose(normals[1][:3], [0, -1, 0]) and np.allclose(normals[1][3:], [0, 1, 0])
    assert np.allclose(normals[2][:3], [0, -1, 0]) and np.allclose(normals[2][3:], [0, 1, 0])


_MESH = st.integers(1, 12).flatmap(lambda n: st.tuples(
    st.just(n), st.lists(st.tuples(st.tuples(*[st.integers(0, n - 1)] * 3), st.integers(-1, 4)),
                         max_size=20), st.integers(0, 4)))


@settings(max_examples=200, deadline=None)
@given(st.lists(_MESH, max_size=6))
def test_splitting_meshes_by_material_is_numpy_unique_of_each_material_s_faces(meshes):
    """All meshes split at once give, per mesh and material with faces, the vertices
    and renumbered faces :func:`numpy.unique` gives for that material's faces alone
    (faces of a material the mesh does not have are left out)."""
    from cga.export.glb import _material_pieces

    cases = [(n, np.array([f for f, _ in faces], dtype=np.int64).reshape(-1, 3),
              np.array([m for _, m in faces], dtype=np.int64), count)
             for n, faces, count in meshes]
    for (_, faces, materials, count), pieces in zip(cases, _material_pieces(cases), strict=True):
        expected = []
        for k in range(count):
            chosen = faces[materials == k]
            if len(chosen):
                used, inverse = np.unique(chosen, return_inverse=True)
                expected.append((k, used, inverse.reshape(-1, 3)))
        assert [k for k, _, _ in pieces] == [k for k, _, _ in expected]
        for (k, used, local), (_, expected_used, expected_local) in zip(pieces, expected):
            assert np.array_equal(used, expected_used)
            assert np.array_equal(local, expected_local) and local.dtype == np.int64
            assert np.array_equal(used[local], faces[materials == k])


def test_local_vertices_are_those_of_each_pivot_s_own_inverse(glb):
    """The batched inverse of the pivots, and the rounding of all nodes at once, put
    every node's vertices where the inverse of its own pivot and its own rounding do
    (structure, at the identity, is not moved at all)."""
    import cga.export.glb as glb_module

    _, nodes, _, _ = glb
    pivots = [glb_module.node_pivot(node) for node in nodes]
    local = glb_module._local_vertices(nodes, glb_module._local_transforms(pivots))
    for node, got in zip(nodes, local, strict=True):
        inverse = np.linalg.inv(glb_module.node_pivot(node))
        vertices = np.asarray(node.mesh.vertices, dtype=float)
        expected = np.round(vertices @ inverse[:3, :3].T + inverse[:3, 3], 6) + 0.0
        assert np.array_equal(got, expected) and got.dtype == expected.dtype, node.path


@settings(max_examples=100, deadline=None)
@given(st.lists(st.integers(1, 6), min_size=1, max_size=8),
       st.sampled_from([(np.float32, 3), (np.uint32, 1), (np.uint8, 4)]), st.randoms())
def test_runs_are_bounded_as_each_alone(lengths, kind, random):
    """The bounds of every run at once are each run's own ``max``/``min`` per component,
    and the runs are the data cut at their starts."""
    from cga.export.glb import _bounded

    dtype, width = kind
    data = np.array([[random.uniform(-1e3, 1e3) if dtype is np.float32 else random.randrange(256)
                      for _ in range(width)] for _ in range(sum(lengths))], dtype=dtype)
    data = data.ravel() if width == 1 else data
    starts = np.cumsum([0, *lengths[:-1]])
    for array, start, length in zip(_bounded(data, starts), starts, lengths, strict=True):
        run = data[start:start + length]
        assert np.array_equal(array.data, run)
        rows = run.reshape(length, -1)
        assert array.high == rows.max(axis=0).tolist() and array.low == rows.min(axis=0).tolist()


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-2, 2) | st.sampled_from([float("nan"), float("inf"), -0.0, 0.5 / 255,
                                                    1.5 / 255, 2.5 / 255]), min_size=4, max_size=4))
def test_colour_steps_are_numpy_s_clip_round_and_cast(rgba):
    """The base colour's 1/255 steps in plain floats are those of the numpy steps the
    writer took (non-finite → 0, clip, round half to even, uint8, / 255)."""
    from cga.export.glb import _byte_steps

    values = np.asarray(rgba, dtype=np.float64)
    values[~np.isfinite(values)] = 0.0
    steps = np.clip(values * 255, 0.0, 255).round().astype(np.uint8)
    assert _byte_steps(rgba) == (steps.astype(np.float64) / 255).tolist()


def _plain(value):
    """json_safe's contract spelled out plainly: numpy → Python, tuples → lists,
    mappings with sorted string keys, sets → sorted lists."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, dict):
        return {str(k): _plain(value[k]) for k in sorted(value, key=str)}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (set, frozenset)):
        return sorted(_plain(v) for v in value)
    return value


_EXTRAS = st.recursive(
    st.none() | st.booleans() | st.integers(-9, 9) | st.floats(allow_nan=False)
    | st.text(max_size=3)
    | st.floats(-9, 9).map(np.float32) | st.integers(-9, 9).map(np.int64)
    | st.frozensets(st.integers(0, 9), max_size=3),
    lambda inner: (st.lists(inner, max_size=3) | st.lists(inner, max_size=3).map(tuple)
                   | st.dictionaries(st.text(max_size=3) | st.integers(0, 20), inner, max_size=4)),
    max_leaves=20)


@settings(max_examples=300, deadline=None)
@given(_EXTRAS)
def test_json_safe_is_its_contract_spelled_out(value):
    """json_safe's shortcuts (plain dicts, lists) give what its contract says, keys in the
    same order."""
    from cga.export.glb import json_safe

    got, expected = json_safe(value), _plain(value)
    assert got == expected and json.dumps(got) == json.dumps(expected)


_ENTRIES = (st.floats() | st.sampled_from([0.0, -0.0, 1.0, 1.0 + 1e-9, 1e-9, 5e-9, 1e-8, -1e-8,
                                           float("nan"), float("inf")]))


@settings(max_examples=300, deadline=None)
@given(st.lists(st.lists(_ENTRIES, min_size=16, max_size=16)
                | st.lists(st.sampled_from([0.0, 1e-9, -3e-9, 2e-8]), min_size=16, max_size=16)
                .map(lambda d: (np.eye(4) + np.reshape(d, (4, 4))).ravel().tolist())
                | st.just(np.eye(4).ravel().tolist()), max_size=5))
def test_matrices_are_written_and_inverted_as_each_alone(entries):
    """All matrices at once are written as each was alone (its columns, or None within
    1e-8 of the identity by ``np.ptp``), and the pivots that are not the identity
    (``np.array_equal``) are the ones inverted: NaN, infinities and ``-0.0`` included."""
    from cga.export.glb import _local_transforms, _written_matrices

    matrices = [np.reshape(e, (4, 4)) for e in entries]
    expected = []
    for matrix in matrices:
        offset = np.asarray(matrix, dtype=np.float64) - np.eye(4)
        near = float(offset.max() - offset.min()) < 1e-8
        expected.append(None if near else np.asarray(matrix, dtype=np.float64).T.ravel().tolist())
    assert json.dumps(_written_matrices(matrices)) == json.dumps(expected)
    with np.errstate(all="ignore"):
        try:
            inverses = _local_transforms(matrices)
        except np.linalg.LinAlgError:  # a singular pivot, as when each was compared alone
            inverses = None
        try:
            expected = _each_inverse(matrices)
        except np.linalg.LinAlgError:
            expected = None
    assert (inverses is None) == (expected is None)
    for got, want in zip(inverses or [], expected or [], strict=True):
        assert (got is None and want is None) or np.array_equal(got, want, equal_nan=True)


def _each_inverse(pivots):
    """The pivots' inverses as the writer took them, comparing each with the identity."""
    moved = [i for i, pivot in enumerate(pivots) if not np.array_equal(pivot, np.eye(4))]
    out = [None] * len(pivots)
    if moved:
        for i, inverse in zip(moved, np.linalg.inv(np.stack([pivots[i] for i in moved]))):
            out[i] = inverse
    return out
