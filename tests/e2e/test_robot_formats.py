"""The robot formats in the clients that consume them (docs/outputs.md).

Every demo is built once with ``--export urdf,sdf,mjcf,usd,json`` and loaded in MuJoCo,
pybullet and usd-core; ``ign sdf -k`` checks the SDF when libsdformat's tool is
installed. Expectations come from the scene JSON and the floor plans (independent of the
exporters): where the walls and doors are, which side a door swings to, its state.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import LineString, Point
from shapely.ops import unary_union

mujoco = pytest.importorskip("mujoco")
pxr = pytest.importorskip("pxr")

import pybullet  # noqa: E402

from cga.pipeline import build  # noqa: E402
from bullet import client  # noqa: E402,F401  (the shared fixture)

DEMOS = sorted((Path(__file__).resolve().parents[2] / "demos").glob("*.grammar"))
SEED = 2
FORMATS = ["json", "urdf", "sdf", "mjcf", "usd"]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module", params=DEMOS, ids=lambda p: p.stem)
def built(request, tmp_path_factory):
    grammar = request.param
    out = tmp_path_factory.mktemp(grammar.stem)
    scene = build(grammar, seed=SEED, out_dir=out, formats=FORMATS, quiet=True, physics=False)
    doc = json.loads((out / f"{grammar.stem}.scene.json").read_text())
    return grammar.stem, out, doc, scene


@pytest.fixture(scope="module")
def house(tmp_path_factory):
    """The house demo with its doors open, and as shipped (closed)."""
    source = next(p for p in DEMOS if p.stem == "house")
    out = {}
    for state in ("closed", "open"):
        folder = tmp_path_factory.mktemp(f"house_{state}")
        grammar = folder / "house.grammar"
        grammar.write_text(source.read_text().replace(
            '.csv")', f'.csv", door_state="{state}")'))
        scene = build(grammar, seed=SEED, out_dir=folder / "out", formats=FORMATS, quiet=True,
                      physics=False)
        doc = json.loads((folder / "out" / "house.scene.json").read_text())
        out[state] = (folder / "out", doc, scene)
    return out


def _leaves(doc):
    """The doors with a leaf: a bare opening (a doorway of usar_floor) has no joint."""
    return [d for d in doc["doors"] if d.get("leaf", True)]


def _ros(point):
    """World (x, y, z), y up → ROS (x, −z, y), written out independently of cga."""
    x, y, z = point
    return np.array([x, -z, y])


# -- MuJoCo -------------------------------------------------------------------------------

def _mj_load(path: Path, extra: str = ""):
    text = path.read_text()
    if extra:
        text = text.replace("</worldbody>", extra + "</worldbody>")
    return mujoco.MjModel.from_xml_string(text) if extra else mujoco.MjModel.from_xml_path(
        str(path))


def _free_bodies(model):
    return [b for b in range(model.nbody) if model.body_jntnum[b] and
            model.jnt_type[model.body_jntadr[b]] == mujoco.mjtJoint.mjJNT_FREE]


def test_mujoco_loads_and_items_rest_for_three_seconds(built):
    name, out, doc, _ = built
    model = _mj_load(out / f"{name}.mjcf.xml")
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    movable = [f for f in doc["furniture"] if not f["is_detail"] and not f["non_collision"]]
    free = _free_bodies(model)
    assert len(free) == len(movable)
    start = data.xpos[free].copy()
    while data.time < 3.0:
        mujoco.mj_step(model, data)
    moved = np.linalg.norm(data.xpos[free] - start, axis=1)
    worst = int(np.argmax(moved)) if len(moved) else 0
    assert moved.max(initial=0.0) <= 0.01, mujoco.mj_id2name(
        model, mujoco.mjtObj.mjOBJ_BODY, free[worst])


def _free_spot(doc, floor, room, radius):
    """A point of the room's free floor at least ``radius`` + 0.2 m from its walls and
    every item (from the scene JSON)."""
    rooms = [r for r in doc["rooms"] if r["floor"] == floor and r["id"] == room]
    from shapely.geometry import Polygon, box

    interior = Polygon(rooms[0]["interior"]["exterior"])
    items = unary_union([box(f["bbox"]["min"][0], f["bbox"]["min"][2], f["bbox"]["max"][0],
                             f["bbox"]["max"][2]) for f in doc["furniture"]
                         if f["floor"] == floor])
    free = interior.buffer(-(radius + 0.2)).difference(items.buffer(radius + 0.2))
    return None if free.is_empty else free.representative_point()


def _sphere(name, position, radius=0.12, velocity=None):
    return (f'<body name="{name}" pos="{position[0]} {position[1]} {position[2]}">'
            f'<freejoint name="{name}_free"/><geom type="sphere" size="{radius}" '
            f'mass="2"/></body>')


def test_mujoco_sphere_rests_on_the_floor(house):
    out, doc, _ = house["closed"]
    floor = doc["floors"][0]
    room = max((r for r in doc["rooms"] if r["floor"] == 0), key=lambda r: r["area"])
    spot = _free_spot(doc, 0, room["id"], 0.12)
    position = _ros((spot.x, floor["floor_y"] + 0.5, spot.y))
    model = _mj_load(out / "house.mjcf.xml", _sphere("probe", position))
    data = mujoco.MjData(model)
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "probe")
    while data.time < 2.0:
        mujoco.mj_step(model, data)
    x, y, z = data.xpos[body]
    assert z == pytest.approx(floor["floor_y"] + 0.12, abs=0.01)  # on the walking surface
    assert np.hypot(x - position[0], y - position[1]) < 0.01  # and stayed there
    assert np.linalg.norm(data.cvel[body]) < 0.05


def _blank_wall_target(doc, floor):
    """A start point and a unit plan direction (x, z) towards a wall's face, with 1.2 m of
    free floor between (no items, no opening within 0.3 m), and the face point."""
    from shapely.geometry import Polygon, box

    items = unary_union([box(f["bbox"]["min"][0], f["bbox"]["min"][2], f["bbox"]["max"][0],
                             f["bbox"]["max"][2]) for f in doc["furniture"]
                         if f["floor"] == floor and not f["non_collision"]
                         and (not f["is_detail"] or f["door"] is not None)]
                        # the stairs' flights and the stairwells are not free floor either
                        + [Polygon(s["polygon"]["exterior"]) for s in doc.get("stairs", [])
                           if floor in s["floors"]])
    for room in (r for r in doc["rooms"] if r["floor"] == floor):
        interior = Polygon(room["interior"]["exterior"])
        for wall in (w for w in doc["walls"] if w["floor"] == floor and room["id"] in w["rooms"]):
            start, end = np.array(wall["start"]), np.array(wall["end"])
            u = (end - start) / np.linalg.norm(end - start)
            for s in np.arange(0.6, wall["length"] - 0.6, 0.1):
                if any(abs(s - o["center"]) < o["width"] / 2 + 0.3 for o in wall["openings"]):
                    continue
                on_wall = start + u * s
                for normal in (np.array([-u[1], u[0]]), np.array([u[1], -u[0]])):
                    face = np.array(on_wall + normal * wall["thickness"] / 2
                                    if not wall["outer"] else on_wall + normal * wall["thickness"])
                    begin = face + normal * 1.2
                    lane = LineString([begin, face + normal * 0.02])
                    if interior.contains(lane) and not lane.buffer(0.15).intersects(items):
                        return begin, -normal, face
    return None


def test_mujoco_sphere_rolled_at_a_wall_is_stopped(house):
    out, doc, _ = house["closed"]
    floor = doc["floors"][0]
    target = _blank_wall_target(doc, 0)
    assert target is not None, "no clear stretch of outer wall to roll at"
    begin, direction, face = target
    radius = 0.12
    position = _ros((begin[0], floor["floor_y"] + radius + 0.002, begin[1]))
    model = _mj_load(out / "house.mjcf.xml", _sphere("probe", position, radius))
    data = mujoco.MjData(model)
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "probe")
    adr = model.jnt_dofadr[model.body_jntadr[body]]
    data.qvel[adr:adr + 2] = _ros((direction[0], 0.0, direction[1]))[:2] * 2.0  # 2 m/s
    face_ros = _ros((face[0], 0.0, face[1]))[:2]
    towards = _ros((direction[0], 0.0, direction[1]))[:2]
    deepest = -np.inf
    while data.time < 2.0:
        mujoco.mj_step(model, data)
        deepest = max(deepest, float((data.xpos[body][:2] - face_ros) @ towards))
    # the sphere's centre never gets closer to the face than its radius, but for the
    # give of MuJoCo's soft contacts (2 cm at 2 m/s), and it did reach the wall
    assert -radius - 0.05 <= deepest <= -radius + 0.02
    final = float((data.xpos[body][:2] - face_ros) @ towards)
    assert final < -radius + 0.005  # stopped on the room's side


def test_mujoco_doors_swing_their_range_without_touching_their_frame(built):
    name, out, doc, _ = built
    model = _mj_load(out / f"{name}.mjcf.xml")
    hinges = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
    assert len(hinges) == len(_leaves(doc))
    if not hinges:
        return
    door_bodies = {int(model.jnt_bodyid[j]) for j in hinges}
    # Every door is driven at once, so two leaves opening towards each other across a
    # corridor would stop each other; each leaf must clear its frame and the furniture,
    # not its neighbours: leaves do not collide with leaves (collision bit 2).
    leaves = np.isin(model.geom_bodyid, sorted(door_bodies))
    model.geom_conaffinity[~leaves] |= 2
    model.geom_contype[leaves] = 2
    model.geom_conaffinity[leaves] = 1
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for j in hinges:  # start closed
        data.qpos[model.jnt_qposadr[j]] = 0.0
    lows, highs = model.jnt_range[hinges, 0], model.jnt_range[hinges, 1]
    assert np.allclose(lows, 0.0) and np.allclose(highs, math.pi / 2)
    dofs = model.jnt_dofadr[hinges]
    reached = np.zeros(len(hinges))
    while data.time < 3.0:
        data.qfrc_applied[dofs] = 30.0  # N·m opening torque on every door
        mujoco.mj_step(model, data)
        reached = np.maximum(reached, data.qpos[model.jnt_qposadr[hinges]])
        for contact in data.contact[:data.ncon]:
            bodies = {int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])}
            if bodies & door_bodies and 0 in bodies:
                pytest.fail(f"a door touches the building at {data.time:.2f} s "
                            f"({contact.dist:.4f} m)")
    assert np.all(reached >= math.pi / 2 - 0.02)


# -- pybullet -----------------------------------------------------------------------------

def _load(client, out, loader):
    if loader == "urdf":
        return client.loadURDF(str(out / "house.urdf"), useFixedBase=True)
    cwd = os.getcwd()
    os.chdir("/")  # mesh URIs resolve against the world file
    try:
        return client.loadSDF(str(out / "house.world.sdf"))[0]
    finally:
        os.chdir(cwd)


def _door_joints(client, body):
    """Revolute joint name → joint index."""
    return {client.getJointInfo(body, j)[1].decode(): j for j in range(client.getNumJoints(body))
            if client.getJointInfo(body, j)[2] == pybullet.JOINT_REVOLUTE}


@pytest.mark.parametrize("loader", ["urdf", "sdf"])
def test_pybullet_door_joints_have_axis_and_limits(client, house, loader):
    out, doc, _ = house["closed"]
    body = _load(client, out, loader)
    joints = _door_joints(client, body)
    assert len(joints) == len(doc["doors"])
    for door in doc["doors"]:
        name = next(n for n in joints if n.startswith(f"floor{door['floor']}_") and
                    n.endswith(f"_door{door['id']}_hinge"))
        info = client.getJointInfo(body, joints[name])
        lower, upper = math.radians(door["limits_degrees"][0]), math.radians(door["limits_degrees"][1])
        assert (info[8], info[9]) == pytest.approx((lower, upper), abs=1e-6)
        assert (info[8], info[9]) == pytest.approx((0.0, math.pi / 2), abs=1e-6)
        # the joint axis in the leaf's frame is vertical, and in the world it is the
        # scene JSON's hinge axis turned to ROS
        state = client.getLinkState(body, joints[name])
        rotation = np.array(client.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        assert rotation @ np.array(info[13]) == pytest.approx(_ros(door["hinge_axis"]), abs=1e-6)
        # the link frame sits on the hinge
        assert np.array(state[4]) == pytest.approx(_ros(door["hinge_point"]), abs=1e-4)


def _doorway(doc, scene, door):
    """Start point 0.7 m into the swing room in front of the door, and the unit plan
    direction through the doorway to the other side."""
    plan = next(p for p in scene.floors if p.index == door["floor"])
    wall = next(w for w in doc["walls"] if w["floor"] == door["floor"] and w["id"] == door["wall"])
    u = np.subtract(wall["end"], wall["start"])
    u = u / np.linalg.norm(u)
    normal = np.array([-u[1], u[0]])
    centre = np.array(door["position"])
    if not plan.room(door["swing_room"]).polygon.contains(Point(*(centre + normal * 0.3))):
        normal = -normal
    return centre + normal * (0.7 + wall["thickness"] / 2), -normal


@pytest.mark.parametrize("loader", ["urdf", "sdf"])
@pytest.mark.parametrize("state", ["closed", "open"])
def test_pybullet_closed_door_stops_a_body_open_one_lets_it_pass(client, house, loader, state):
    out, doc, scene = house[state]
    body = _load(client, out, loader)
    joints = _door_joints(client, body)
    index = json.loads((out / "house.urdf.json").read_text())
    for entry in index["doors"]:  # SDF and URDF start closed; the index has the build's angle
        client.resetJointState(body, joints[entry["joint"]], entry["position"])
    door = next(d for d in doc["doors"] if d["floor"] == 0 and not d["front"])
    assert door["state"] == state
    start, direction = _doorway(doc, scene, door)
    floor_y = doc["floors"][0]["floor_y"]
    radius = 0.15
    shape = client.createCollisionShape(pybullet.GEOM_SPHERE, radius=radius)
    probe = client.createMultiBody(3.0, shape, basePosition=_ros((start[0], floor_y + radius +
                                                                 0.01, start[1])))
    client.resetBaseVelocity(probe, _ros((direction[0], 0.0, direction[1])) * 2.0)
    centre = np.array(door["position"])
    crossed = -np.inf
    for _ in range(480):
        client.stepSimulation()
        x, y, _ = client.getBasePositionAndOrientation(probe)[0]
        world = np.array([x, -y])  # ROS (x, y) → plan (x, z)
        crossed = max(crossed, float((world - centre) @ direction))
    if state == "closed":
        assert crossed < 0.0  # never reached the wall's centre line
    else:
        assert crossed > 0.5  # through the doorway into the other room


# -- USD ----------------------------------------------------------------------------------

def test_usd_opens_and_validates_with_physics_and_labels(built):
    from pxr import Usd, UsdGeom, UsdPhysics, UsdSemantics, UsdShade, UsdValidation

    name, out, doc, _ = built
    stage = Usd.Stage.Open(str(out / f"{name}.usdc"))
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    errors = UsdValidation.ValidationContext(validators).Validate(stage)
    assert [e.GetMessage() for e in errors] == []
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    prims = list(stage.Traverse())
    structure = [n for n in doc["nodes"] if n["kind"] != "furniture"]
    assert len(prims) > len(doc["nodes"]) + len(structure)
    materials = [p for p in prims if p.IsA(UsdShade.Material)]
    assert len(materials) >= 2
    meshes = [p for p in prims if p.IsA(UsdGeom.Mesh) and
              UsdGeom.Imageable(p).ComputePurpose() == UsdGeom.Tokens.default_]
    assert all(UsdShade.MaterialBindingAPI(p).ComputeBoundMaterial()[0] for p in meshes)
    colliders = [p for p in prims if p.HasAPI(UsdPhysics.CollisionAPI)]
    assert len(colliders) >= len(structure)
    joints = [UsdPhysics.RevoluteJoint(p) for p in prims if p.IsA(UsdPhysics.RevoluteJoint)]
    assert len(joints) == len(_leaves(doc))
    for joint in joints:
        limits = sorted([joint.GetLowerLimitAttr().Get(), joint.GetUpperLimitAttr().Get()])
        assert limits in ([0.0, 90.0], [-90.0, 0.0])
        assert joint.GetBody1Rel().GetTargets()
    bodies = [p for p in prims if p.HasAPI(UsdPhysics.RigidBodyAPI)]
    movable = [f for f in doc["furniture"] if not f["is_detail"] and not f["non_collision"]]
    assert len(bodies) == len(movable) + len(_leaves(doc))
    labelled = [p for p in prims if p.HasAPI(UsdSemantics.LabelsAPI, "class")]
    nodes = {p.GetAttribute("cga:node").Get() for p in labelled}
    assert nodes == {n["path"] for n in doc["nodes"]}  # storeys' links are not labelled
    from pxr import UsdLux

    lights = [p for p in prims if p.IsA(UsdLux.SphereLight)]
    assert len(lights) == len(doc["lights"])


# -- SDFormat -----------------------------------------------------------------------------

def _sdf_checker() -> list[str] | None:
    for tool in ("gz", "ign"):
        path = shutil.which(tool)
        if path is None:
            continue
        probe = subprocess.run([path, "sdf", "--help"], capture_output=True, text=True,
                               timeout=60, check=False)
        if probe.returncode == 0:
            return [path, "sdf", "-k"]
    return None


@pytest.mark.skipif(_sdf_checker() is None, reason="libsdformat's gz/ign sdf tool not installed")
def test_sdf_passes_sdformat_check_without_warnings(built):
    name, out, _, _ = built
    result = subprocess.run([*_sdf_checker(), str(out / f"{name}.world.sdf")],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0 and "Valid" in result.stdout, result.stdout + result.stderr
    assert "Warning" not in result.stderr and "Error" not in result.stderr, result.stderr
    root = ET.parse(out / f"{name}.world.sdf").getroot()
    assert all("concave" not in e.attrib for e in root.iter())
