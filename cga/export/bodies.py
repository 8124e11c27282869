"""Rigid bodies for the robot exporters (URDF, SDF), in the ROS frame.

A build becomes one static **building** body (every static node that is not furniture:
walls, slabs, ceilings, masses, merged into one concave triangle mesh) plus one body per
**furniture item** (every ``furniture`` node). An item's link frame sits at its centre
of mass (its convex parts at uniform density) and is turned by the item's yaw
(``rotation`` extra, quarter turns about world +y = ROS +z), so:

* ``pybullet.loadURDF(item_urdf, basePosition=pose.position,
  baseOrientation=pose.quaternion_xyzw)`` puts the item where it stands, and
  ``getBasePositionAndOrientation`` reports that same pose (the link origin is the
  centre of mass, so pybullet's inertial-frame convention does not shift it);
* a top-heavy or overhanging item (a pedestal washbasin) balances as it does in the
  physics check, because its centre of mass is where its material is;
* the inertia is that of the item's box, a solid of the item's extents in its own frame
  (exact extents, since turns are quarter turns), about the centre of mass.

Solid items are dynamic with the mass of their ``mass`` extra and collide through their
convex parts (shrunk for Bullet's margin, :mod:`cga.collision`), one collision element
each. Static
furniture (door leaves, window frames, rugs) is fixed and visual only: the physics and
navigability checks ignore it, a rug lies under what stands on it, and a door leaf must
not close the gap the navigability check drove through.

:func:`write_body_meshes` writes the OBJ files both URDF and SDF refer to, under
``meshes/`` next to the world file.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from cga.collision import collision_parts, shrink_part
from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .frames import WORLD_TO_ROS, RosPose, pose_to_ros, world_to_ros
from .obj import MeshGroup, mtl_text, node_groups, node_material, obj_text, vertex_colors
from .palette import RGB, node_color

__all__ = ["RobotBody", "BodyFiles", "MESH_DIR", "robot_bodies",
           "write_body_meshes", "write_bodies", "box_inertia", "centre_of_mass",
           "numbers_text"]

MESH_DIR = "meshes"
"""Folder (relative to the output folder) holding the robot exporters' OBJ files."""



@dataclass(frozen=True)
class RobotBody:
    """One rigid body in the ROS frame.

    ``visual`` holds the visual meshes and ``collisions`` the collision meshes, all in
    the link frame (an item's convex parts; the building's one concave mesh).
    ``inertia`` is the diagonal (ixx, iyy, izz) in kg·m² about the link origin.
    ``label`` names its mesh files (the model name, or ``building``).
    """

    name: str
    node: str | None
    label: str
    pose: RosPose
    visual: tuple[MeshGroup, ...]
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


def _identifier(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]+", "_", text).strip("_") or "item"


def _unique(names: list[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for name in names:
        count = seen.get(name, 0) + 1
        seen[name] = count
        out.append(name if count == 1 else f"{name}_{count}")
    return out


def centre_of_mass(parts: Sequence[Any]) -> np.ndarray:
    """World centre of mass of solid convex parts of uniform density (the volume-weighted
    mean of their centroids); the bounding-box centre if they enclose no volume."""
    solids = [p if p.is_volume else p.convex_hull for p in parts]
    volumes = np.array([max(float(s.volume), 0.0) for s in solids])
    if volumes.sum() <= 0.0:
        return np.asarray(trimesh_bounds(parts), dtype=float).mean(axis=0)
    return np.average([s.center_mass for s in solids], axis=0, weights=volumes)


def trimesh_bounds(meshes: Sequence[Any]) -> np.ndarray:
    """(2, 3) bounds of several meshes together."""
    bounds = np.array([m.bounds for m in meshes], dtype=float)
    return np.array([bounds[:, 0].min(axis=0), bounds[:, 1].max(axis=0)])


def _item_body(node: SceneNode, name: str) -> RobotBody:
    item = node.item
    turns = item.rotation % 4 if item is not None else 0
    parts = collision_parts(node) if not node.static else (node.parts or (node.mesh,))
    pose = pose_to_ros(centre_of_mass(parts), 90.0 * turns)
    # link frame: the ROS axes turned by the yaw, origin at the centre of mass; a ROS
    # point p has link coordinates yawᵀ (p − origin), i.e. (p − origin) @ yaw as rows
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    yaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    origin = np.asarray(pose.position)

    def local(mesh) -> np.ndarray:
        return (world_to_ros(mesh.vertices) - origin) @ yaw

    label = _identifier(item.model if item is not None else "item")
    material, color = node_material(node)
    visual = (MeshGroup(label, local(node.mesh), np.asarray(node.mesh.faces), material,
                        vertex_colors(node.mesh)),)
    if node.static:  # details and rugs: seen, not touched (the checks ignore them too)
        return RobotBody(name=name, node=node.path, label=label, pose=pose, visual=visual,
                         materials={material: color}, collisions=(), mass=0.0,
                         inertia=(0.0, 0.0, 0.0), static=True, concave=False, color=color)
    mass = item.mass if item is not None else 0.0
    if not mass > 0.0:
        raise ExportError(f"furniture node '{node.path}' has no positive mass "
                          f"(got {mass!r}); robot exports need the mass of every movable item")
    solids = [local(p) for p in parts]
    collisions = tuple(MeshGroup(f"{label}_part{k}", shrink_part(v),
                                 np.asarray(p.faces), material)
                       for k, (p, v) in enumerate(zip(parts, solids)))
    stacked = np.vstack(solids)
    return RobotBody(
        name=name, node=node.path, label=label, pose=pose, visual=visual,
        materials={material: color}, collisions=collisions, mass=mass,
        inertia=box_inertia(mass, stacked.max(axis=0) - stacked.min(axis=0)),
        static=False, concave=False, color=color)


def robot_bodies(scene: Scene, nodes: Sequence[SceneNode]) -> tuple[RobotBody, list[RobotBody]]:
    """The building body and the item bodies of a build.

    Parameters
    ----------
    scene:
        The build (only used in messages).
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
        raise ExportError(f"robot export of '{scene.name}': the scene has no building "
                          f"geometry (walls, slabs or masses) to put in the world")
    groups, materials = node_groups(structure, transform=WORLD_TO_ROS)
    offsets = np.cumsum([0] + [len(g.vertices) for g in groups[:-1]])
    merged = MeshGroup("building", np.vstack([g.vertices for g in groups]),
                       np.vstack([g.faces + k for g, k in zip(groups, offsets)]), "wall")
    building = RobotBody(
        name="building", node=None, label="building", pose=RosPose((0.0, 0.0, 0.0), 0.0),
        visual=tuple(groups), materials=materials, collisions=(merged,), mass=0.0,
        inertia=(0.0, 0.0, 0.0), static=True, concave=True, color=node_color("wall"))
    furniture = [n for n in nodes if n.kind == "furniture" and len(n.mesh.faces)]
    names = _unique([_identifier(n.path.replace("/furniture/", "/")) for n in furniture])
    return building, [_item_body(n, name) for n, name in zip(furniture, names)]


def _write_once(folder: Path, stem: str, text: str) -> str:
    """Write ``text`` to ``<folder>/<stem>.<hash>.obj`` unless that file exists (the name
    is derived from the content, so an existing file is this one: identical items share
    files, and the URDF and SDF exporters share them in one output folder)."""
    digest = hashlib.sha1(text.encode("utf-8")).hexdigest()[:12]
    file_name = f"{stem}.{digest}.obj"
    if not (folder / file_name).is_file():
        atomic_write(folder / file_name, text)
    return f"{MESH_DIR}/{file_name}"


def write_body_meshes(bodies: Sequence[RobotBody], out_dir: Path, name: str
                      ) -> dict[str, BodyFiles]:
    """Write the bodies' visual and collision OBJs and one MTL under ``meshes/``.

    Files are named by the body's label and a hash of their content
    (``meshes/<name>.<label>.<hash>.obj``), so items with equal meshes in their own
    frames (the same model, size and yaw convention) share files.

    Returns
    -------
    dict
        Body name → its files, relative to ``out_dir``.
    """
    folder = Path(out_dir) / MESH_DIR
    materials: dict[str, RGB] = {}
    for body in bodies:
        materials.update(body.materials)
    mtl_name = f"{name}.mtl"
    atomic_write(folder / mtl_name, mtl_text(materials))
    header = "cga mesh: ROS frame axes (z up), metres, relative to its body's link frame"
    files: dict[str, BodyFiles] = {}
    for body in bodies:
        visual = _write_once(folder, f"{name}.{body.label}",
                             obj_text(body.visual, mtl_file=mtl_name, header=header))
        collisions = tuple(
            _write_once(folder, f"{name}.{body.label}.collision",
                        obj_text([part], mtl_file=None, header=header + "; collision"))
            for part in body.collisions)
        files[body.name] = BodyFiles(visual, f"{MESH_DIR}/{mtl_name}", collisions)
    return files


def write_bodies(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str
                 ) -> tuple[list[RobotBody], dict[str, BodyFiles]]:
    """The building body and the item bodies (:func:`robot_bodies`), with their mesh
    files written under ``out_dir`` (:func:`write_body_meshes`): what the URDF and SDF
    exporters both start from.

    Returns
    -------
    (bodies, files)
        ``bodies`` with the building first; ``files`` by body name.
    """
    building, items = robot_bodies(scene, nodes)
    bodies = [building, *items]
    return bodies, write_body_meshes(bodies, Path(out_dir), name)
