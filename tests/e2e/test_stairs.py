"""End to end: multi-storey demos get one stair per pair of consecutive floors (DESIGN §12).

Each build is checked from its written files with code independent of the stair code:
the stairwell is read back from the upper slab's mesh in the glb, step heights from the
stair's mesh, reachability from the doors and stair edges of the scene JSON (networkx),
and the SDF through pybullet.
"""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
import trimesh
from shapely.geometry import MultiPolygon, Polygon
from shapely.ops import unary_union

from glb_nodes import mesh_node_names, node_mesh
from items import item_info

from cga.checks.navigability import check_navigability
from cga.pipeline import build
from cga.scene import SceneNode

ROOT = Path(__file__).resolve().parents[2]
STOREYS = {"house": 2, "office": None, "apartment_block": 3}
OUTSIDE = -1


def _polygon(data: dict) -> Polygon:
    return Polygon(data["exterior"], data["holes"])


@pytest.fixture(scope="module", params=[("house", 3), ("office", 1), ("apartment_block", 2)],
                ids=lambda p: f"{p[0]}-seed{p[1]}")
def built(request, tmp_path_factory):
    name, seed = request.param
    out = tmp_path_factory.mktemp(name)
    build(ROOT / "demos" / f"{name}.grammar", seed=seed, out_dir=out,
          formats=("glb", "json", "sdf"), quiet=True)
    data = json.loads((out / f"{name}.scene.json").read_text(encoding="utf-8"))
    glb = trimesh.load(io.BytesIO((out / f"{name}.glb").read_bytes()), file_type="glb")
    return data, glb, out, name


def _mesh(glb: trimesh.Scene, path: str) -> trimesh.Trimesh:
    return node_mesh(glb, path)


def test_one_stair_per_pair_of_consecutive_floors(built):
    data, _, _, _ = built
    floors = sorted(f["index"] for f in data["floors"])
    assert len(floors) >= 2
    assert sorted(tuple(s["floors"]) for s in data["stairs"]) == [(i, i + 1) for i in floors[:-1]]
    tops = [f["index"] for f in data["floors"] if f["is_top"]]
    assert tops == [floors[-1]]


def test_the_stairwell_above_has_the_stairs_footprint(built):
    data, glb, _, _ = built
    for stair in data["stairs"]:
        upper = next(f for f in data["floors"] if f["index"] == stair["floors"][1])
        slab = _mesh(glb, f"floor{upper['index']}/slab")
        # the slab's walking surface: its upward triangles, seen from above
        top = slab.triangles[slab.face_normals[:, 1] > 0.99][:, :, [0, 2]]
        surface = unary_union([Polygon(t).buffer(1e-7) for t in top])
        polygons = list(surface.geoms) if isinstance(surface, MultiPolygon) else [surface]
        holes = [Polygon(h) for p in polygons for h in p.interiors]
        assert len(holes) == 1
        hole, well = holes[0], _polygon(stair["polygon"])
        iou = hole.intersection(well).area / hole.union(well).area
        assert iou >= 0.99


def test_the_stair_stands_in_circulation_on_both_floors(built):
    data, _, _, _ = built
    for stair in data["stairs"]:
        well = _polygon(stair["polygon"])
        for floor, room_id in zip(stair["floors"], stair["rooms"]):
            room = next(r for r in data["rooms"] if r["floor"] == floor and r["id"] == room_id)
            assert room["circulation"] and room["type"] == "Stair"
            assert _polygon(room["polygon"]).buffer(1e-6).covers(well)
            for landing in stair["landings"]:
                assert _polygon(room["polygon"]).buffer(1e-6).covers(_polygon(landing))
        # no furniture on the stair or its landings, on either floor
        for item in data["furniture"]:
            if item["floor"] in stair["floors"] and not item["is_detail"]:
                (x0, _, z0), (x1, _, z1) = item["bbox"]["min"], item["bbox"]["max"]
                footprint = Polygon([(x0, z0), (x1, z0), (x1, z1), (x0, z1)])
                for area in [well] + [_polygon(p) for p in stair["landings"]]:
                    assert footprint.intersection(area).area < 1e-9, item["node"]


def test_step_dimensions_are_within_the_parameters(built):
    data, glb, _, name = built
    max_rise, min_going, min_width = (0.18, 0.27, 1.1) if name == "apartment_block" else (0.19, 0.25, 0.9)
    for stair in data["stairs"]:
        assert stair["rise"] <= max_rise + 1e-9 and stair["going"] >= min_going - 1e-9
        assert stair["width"] >= min_width - 1e-9
        assert stair["steps"] * stair["rise"] == pytest.approx(stair["top_y"] - stair["bottom_y"], abs=1e-5)
        # the upward faces of the stair's mesh sit at the floor plus whole numbers of risers
        mesh = _mesh(glb, stair["node"])
        up = mesh.face_normals[:, 1] > 0.99
        heights = np.unique(np.round(mesh.triangles_center[up][:, 1], 4))
        steps = (heights - stair["bottom_y"]) / stair["rise"]
        assert np.allclose(steps, np.round(steps), atol=1e-3)
        # one upward face per riser but the last, which lands on the upper floor
        assert np.array_equal(np.round(steps), np.arange(1, stair["steps"]))
        assert mesh.is_watertight


def test_a_roof_and_rails(built):
    data, _, out, name = built
    top = max(f["index"] for f in data["floors"])
    names = mesh_node_names(out / f"{name}.glb")
    assert f"floor{top}/roof" in names
    for stair in data["stairs"]:
        assert f"floor{stair['floors'][1]}/stairwell{stair['id']}/rail" in names


def test_every_room_is_reachable_from_the_front_door_through_the_stairs(built):
    data, _, _, _ = built
    reach = data["checks"]["navigability"]
    assert reach["passed"] and reach["radius_m"] == 0.25
    upper = [f for f in reach["floors"] if f["floor"] > 0]
    assert all(f["start"] == "stair" and f["via_stairs"] for f in upper)
    assert data["checks"]["physics"]["passed"]
    # independently: rooms as (floor, id) nodes, doors and stair edges as edges
    graph = nx.Graph()
    graph.add_nodes_from((r["floor"], r["id"]) for r in data["rooms"])
    for door in data["doors"]:
        a, b = door["rooms"]
        graph.add_edge((door["floor"], a) if a != OUTSIDE else "outside",
                       (door["floor"], b) if b != OUTSIDE else "outside")
    stair_edges = [e for e in data["room_graph"] if "stair" in e]
    assert len(stair_edges) == len(data["stairs"])
    for edge in stair_edges:
        graph.add_edge((edge["floor"], edge["rooms"][0]), (edge["to_floor"], edge["rooms"][1]))
    assert nx.node_connected_component(graph, "outside") >= set(graph.nodes) - {"outside"}


@pytest.mark.physics
def test_pybullet_loads_the_sdf_and_the_stair_collides(built):
    import pybullet

    data, _, out, name = built
    client = pybullet.connect(pybullet.DIRECT)
    try:
        pybullet.loadSDF(str(out / f"{name}.world.sdf"), physicsClientId=client)
        stair = data["stairs"][0]
        flight = stair["flights"][0]
        dx, dz = flight["direction"]
        for k in (1, flight["risers"] // 2):
            along = (k - 0.5) * flight["going"]
            x, z = flight["start"][0] + along * dx, flight["start"][1] + along * dz
            top = flight["base_y"] + k * flight["rise"]
            # ROS frame: (x, y, z) = (x, -z_world, y_world)
            [hit] = pybullet.rayTest([x, -z, top + 0.5], [x, -z, top - 0.05], physicsClientId=client)
            assert hit[0] >= 0, f"the ray down onto tread {k} hits nothing"
            assert hit[3][2] == pytest.approx(top, abs=0.02)
    finally:
        pybullet.disconnect(client)


@pytest.mark.physics
def test_a_dropped_body_comes_to_rest_on_a_step(built):
    import pybullet

    data, glb, _, _ = built
    stair = data["stairs"][0]
    mesh = _mesh(glb, stair["node"])
    flight = stair["flights"][0]
    k = 3
    dx, dz = flight["direction"]
    along = (k - 0.5) * flight["going"]
    x, z = flight["start"][0] + along * dx, flight["start"][1] + along * dz
    top = flight["base_y"] + k * flight["rise"]
    client = pybullet.connect(pybullet.DIRECT)
    try:
        pybullet.setGravity(0, -9.81, 0, physicsClientId=client)  # y up, as the glb
        shape = pybullet.createCollisionShape(
            pybullet.GEOM_MESH, vertices=mesh.vertices.tolist(), indices=mesh.faces.ravel().tolist(),
            flags=pybullet.GEOM_FORCE_CONCAVE_TRIMESH, physicsClientId=client)
        pybullet.createMultiBody(0, shape, physicsClientId=client)
        half = 0.08
        box = pybullet.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[half] * 3,
                                            physicsClientId=client)
        body = pybullet.createMultiBody(1.0, box, basePosition=[x, top + 0.3, z],
                                        physicsClientId=client)
        for _ in range(480):
            pybullet.stepSimulation(physicsClientId=client)
        (px, py, pz), _ = pybullet.getBasePositionAndOrientation(body, physicsClientId=client)
        speed = np.linalg.norm(pybullet.getBaseVelocity(body, physicsClientId=client)[0])
        assert py == pytest.approx(top + half, abs=0.01)
        assert math.hypot(px - x, pz - z) < 0.05 and speed < 0.01
    finally:
        pybullet.disconnect(client)


def test_a_blocked_top_landing_cuts_off_the_upper_floor_and_says_where(tmp_path):
    scene = build(ROOT / "demos" / "house.grammar", seed=3, formats=(), physics=False, quiet=True)
    nodes = scene.nodes
    assert check_navigability(scene, nodes).passed
    upper = scene.floors[1]
    stair = upper.stair_down
    landing = stair.landings[1]
    x0, z0, x1, z1 = landing.bounds
    crate = trimesh.creation.box(extents=[x1 - x0, 1.0, z1 - z0])
    crate.apply_translation([(x0 + x1) / 2, upper.floor_y + 0.5, (z0 + z1) / 2])
    blocker = SceneNode("floor1/crate", "furniture", crate, static=False, parts=(crate,),
                        item=item_info("crate", room=stair.rooms[1]))
    report = check_navigability(scene, [*nodes, blocker])
    ground, first = report.floors
    assert ground.passed and ground.stair_up_reached
    assert not first.passed and not any(r.reachable for r in first.rooms)
    reasons = {reason for r in first.rooms for reason in r.reasons}
    [reason] = reasons
    px, pz = stair.landing_points[1]
    assert "top landing" in reason and f"({px:.2f}, {pz:.2f})" in reason
    assert "floor1/crate" in reason and f"stair {stair.id}" in reason
    assert "floor 1" in report.summary()


STRAIGHT = """
Lot: rectangle(16, 10)
Rules:
Lot --> extrude({height}) Body
Body --> repeated_split("Y", 3){{Ground, Upper}}
Ground --> make_floor(7, 0.2, 2>1.2>1.2, 0.9, 2.1, stair = "straight", corridor = "spine",
                      corridor_width = 1.6, min_room_width = 2, min_room_area = 4) Floor
Upper --> make_floor(7, 0.2, 2>1.2>1.2, 0.9, 2.1, stair = "straight", corridor = "spine",
                     corridor_width = 1.6, min_room_width = 2, min_room_area = 4) Floor
Floor --> case floor == 0 : type_rooms("house_types.csv") Typed
        | else : type_rooms("house_upper_types.csv") Typed
"""


def test_a_straight_stair_joins_two_storeys_and_the_robot_climbs_it(tmp_path):
    path = tmp_path / "straight.grammar"
    path.write_text(STRAIGHT.format(height=6), encoding="utf-8")
    for seed in range(3):
        scene = build(path, seed=seed, formats=("json",), out_dir=tmp_path / str(seed), quiet=True)
        data = json.loads((tmp_path / str(seed) / "straight.scene.json").read_text(encoding="utf-8"))
        [stair] = data["stairs"]
        assert stair["kind"] == "straight" and len(stair["flights"]) == 1
        bottom, top = (_polygon(p) for p in stair["landings"])
        assert bottom.distance(top) > 1.0  # the landings are at the two ends of the flight
        assert data["checks"]["navigability"]["passed"], data["checks"]["navigability"]["summary"]


def test_a_straight_stair_through_three_storeys_is_refused(tmp_path):
    from cga.errors import DerivationError

    path = tmp_path / "straight.grammar"
    path.write_text(STRAIGHT.format(height=9), encoding="utf-8")
    with pytest.raises(DerivationError, match='straight stair joins two storeys'):
        build(path, formats=(), physics=False, quiet=True)


def test_storeys_without_a_stair_are_reported_cut_off(tmp_path):
    """``stair = "none"`` on a stack of storeys leaves the upper floor without a way up:
    the build says so with a warning, and no message claims a stair that is not there."""
    grammar = tmp_path / "no_stair.grammar"
    grammar.write_text(
        'units = 1;\nLot: rectangle(14, 10)\nRules:\nLot --> extrude(6) Body\n'
        'Body --> repeated_split("Y", 3){Storey}\n'
        'Storey --> make_floor(6, 0.2, 2>1.2>1.3, 0.9, 2.1, corridor = "spine", '
        'corridor_width = 1.6, min_room_width = 2, min_room_area = 4, stair = "none") Floor\n'
        'Floor --> case floor == 0 : type_rooms("house_types.csv") Typed\n'
        '        | else : type_rooms("house_upper_types.csv") Typed\n', encoding="utf-8")
    scene = build(grammar, seed=0, formats=(), physics=False, quiet=True)
    assert not any(plan.stairs for plan in scene.floors)
    messages = [(d.level, d.floor, d.message) for d in scene.all_diagnostics()]
    assert [(level, floor) for level, floor, text in messages
            if "no stair comes up to floor" in text] == [("warning", 1)]
    assert not any("the stair arrives" in text for _, _, text in messages)
