"""Rigid bodies for the robot exporters (URDF, SDF), in the ROS frame.

A build becomes one static **building** body (every static node that is not furniture:
walls, slabs, ceilings, masses, merged into one concave triangle mesh) plus one body per
**furniture item** (every ``furniture`` node). An item's link frame sits at the centre
of its bounding box and is turned by the item's yaw (``rotation`` extra, quarter turns
about world +y = ROS +z), so:

* ``pybullet.loadURDF(item_urdf, basePosition=pose.position,
  baseOrientation=pose.quaternion_xyzw)`` puts the item where it stands, and
  ``getBasePositionAndOrientation`` reports that same pose (the centre of mass is the
  link origin, so pybullet's inertial-frame convention does not shift it);
* the inertia is that of the item's box (exact extents, since turns are quarter turns).

Solid items are dynamic with the mass of their ``mass`` extra; detail items and
non-colliding items (rugs) are fixed (mass 0). Collision geometry of an item is its
convex parts, one collision element each.

:func:`write_body_meshes` writes the OBJ files both URDF and SDF refer to, under
``meshes/`` next to the world file.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .frames import WORLD_TO_ROS, RosPose, pose_to_ros, world_to_ros
from .obj import MeshGroup, mtl_text, node_groups, obj_text
from .palette import RGB, node_color

__all__ = ["RobotBody", "BodyFiles", "MESH_DIR", "robot_bodies", "write_body_meshes",
           "box_inertia", "numbers_text"]

MESH_DIR = "meshes"
"""Folder (relative to the output folder) holding the robot exporters' OBJ files."""


@dataclass(frozen=True)
class RobotBody:
    """One rigid body in the ROS frame.

    ``groups`` are the visual meshes in the link frame, ``collisions`` the collision
    meshes in the link frame (convex parts; for the building one concave mesh).
    ``inertia`` is the diagonal (ixx, iyy, izz) in kg·m² about the link origin.
    """

    name: str
    node: str | None
    pose: RosPose
    groups: tuple[MeshGroup, ...]
    materials: dict[str, RGB]
    collisions: tuple[MeshGroup, ...]
    mass: float
    inertia: tuple[float, float, float]
    static: bool
    concave: bool
    color: RGB


@dataclass(frozen=True)
class BodyFiles:
    """Mesh files of a body, relative to the output folder (POSIX separators)."""

    visual: str
    material: str
    collisions: tuple[str, ...]

    def paths(self) -> list[str]:
        """Every file of the body."""
        return [self.visual, self.material, *self.collisions]


def box_inertia(mass: float, extents: Sequence[float]) -> tuple[float, float, float]:
    """Principal moments (ixx, iyy, izz) of a solid box of ``mass`` kg and ``extents``
    (x, y, z) metres about its centre: m(b² + c²)/12 and permutations."""
    a, b, c = (float(e) for e in extents)
    return (mass * (b * b + c * c) / 12.0, mass * (a * a + c * c) / 12.0,
            mass * (a * a + b * b) / 12.0)


def numbers_text(values: Sequence[float]) -> str:
    """Numbers as XML attribute/element text: space separated, at most 6 decimals."""
    out = []
    for value in values:
        text = f"{float(value) + 0.0:.6f}".rstrip("0").rstrip(".")
        out.append("0" if text in ("", "-0") else text)
    return " ".join(out)


def _identifier(path: str) -> str:
    text = path.replace("/furniture/", "/")
    return re.sub(r"[^A-Za-z0-9_]+", "_", text).strip("_") or "item"


def _unique(names: list[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for name in names:
        count = seen.get(name, 0) + 1
        seen[name] = count
        out.append(name if count == 1 else f"{name}_{count}")
    return out


def _item_body(node: SceneNode, name: str) -> RobotBody:
    turns = int(node.extras.get("rotation", 0)) % 4
    centre_world = np.asarray(node.mesh.bounds, dtype=float).mean(axis=0)
    pose = pose_to_ros(centre_world, 90.0 * turns)
    # link frame: ROS axes turned by the yaw about the bounding-box centre
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    yaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    to_link = yaw.T @ WORLD_TO_ROS
    origin = np.asarray(pose.position)

    def local(mesh) -> np.ndarray:
        return world_to_ros(mesh.vertices) @ yaw - origin @ yaw

    parts = node.parts or (node.mesh,)
    collisions = tuple(MeshGroup(f"{name}_part{k}", local(p), np.asarray(p.faces), "collision")
                       for k, p in enumerate(parts))
    groups, materials = node_groups([node], transform=to_link)
    groups = [MeshGroup(g.name, g.vertices - origin @ yaw, g.faces, g.material) for g in groups]
    stacked = np.vstack([g.vertices for g in collisions])
    extents = stacked.max(axis=0) - stacked.min(axis=0)
    static = bool(node.static)
    if static:
        mass = 0.0
    else:
        mass = float(node.extras.get("mass", 0.0))
        if not mass > 0.0:
            raise ExportError(f"furniture node '{node.path}' has no positive 'mass' extra "
                              f"(got {node.extras.get('mass')!r}); robot exports need the "
                              f"mass of every movable item")
    return RobotBody(
        name=name, node=node.path, pose=pose, groups=tuple(groups), materials=materials,
        collisions=collisions, mass=mass,
        inertia=(0.0, 0.0, 0.0) if static else box_inertia(mass, extents),
        static=static, concave=False, color=node_color(node.kind, node.extras))


def robot_bodies(scene: Scene, nodes: Sequence[SceneNode]) -> tuple[RobotBody, list[RobotBody]]:
    """The building body and the item bodies of a build.

    Parameters
    ----------
    scene:
        The build (names the building body).
    nodes:
        Its scene nodes in world coordinates.

    Returns
    -------
    (building, items)
        ``items`` in node order, with unique names made from the node paths
        (``floor0/room1_Livingroom/furniture/sofa`` → ``floor0_room1_Livingroom_sofa``).

    Raises
    ------
    ExportError
        There is no static geometry to make the building from, or a movable item has no
        positive ``mass`` extra.
    """
    structure = [n for n in nodes if n.kind != "furniture" and len(n.mesh.faces)]
    if not structure:
        raise ExportError("robot export: the scene has no building geometry (no static "
                          "walls, slabs or masses) to put in the world")
    groups, materials = node_groups(structure, transform=WORLD_TO_ROS)
    merged = MeshGroup("building", np.vstack([g.vertices for g in groups]),
                       np.vstack(_offset_faces(groups)), "building")
    building = RobotBody(
        name="building", node=None, pose=RosPose((0.0, 0.0, 0.0), 0.0), groups=tuple(groups),
        materials=materials, collisions=(merged,), mass=0.0, inertia=(0.0, 0.0, 0.0),
        static=True, concave=True, color=node_color("wall", {}))
    furniture = [n for n in nodes if n.kind == "furniture" and len(n.mesh.faces)]
    names = _unique([_identifier(n.path) for n in furniture])
    return building, [_item_body(n, name) for n, name in zip(furniture, names)]


def _offset_faces(groups: Sequence[MeshGroup]) -> list[np.ndarray]:
    out, offset = [], 0
    for g in groups:
        out.append(np.asarray(g.faces) + offset)
        offset += len(g.vertices)
    return out


def write_body_meshes(bodies: Sequence[RobotBody], out_dir: Path, name: str
                      ) -> dict[str, BodyFiles]:
    """Write every body's visual OBJ (+ MTL) and collision OBJs under ``meshes/``.

    Returns
    -------
    dict
        Body name → its files, relative to ``out_dir``.
    """
    folder = Path(out_dir) / MESH_DIR
    files: dict[str, BodyFiles] = {}
    for body in bodies:
        stem = f"{name}.{body.name}"
        header = (f"cga body '{body.name}': ROS frame (z up, metres), relative to the "
                  f"body's link frame")
        atomic_write(folder / f"{stem}.mtl", mtl_text(body.materials))
        atomic_write(folder / f"{stem}.obj",
                     obj_text(body.groups, mtl_file=f"{stem}.mtl", header=header))
        collision_files = []
        for k, part in enumerate(body.collisions):
            part_name = f"{stem}.collision{k}.obj"
            atomic_write(folder / part_name, obj_text([part], mtl_file=None,
                                                      header=header + ", collision"))
            collision_files.append(f"{MESH_DIR}/{part_name}")
        files[body.name] = BodyFiles(f"{MESH_DIR}/{stem}.obj", f"{MESH_DIR}/{stem}.mtl",
                                     tuple(collision_files))
    return files
