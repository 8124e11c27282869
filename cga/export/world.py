"""One description of a build as a robot world, which every robot format writes.

URDF, SDF, MJCF and USD (docs/outputs.md) differ in syntax, not in content: each gets the
same :class:`World`, built once by :func:`robot_world`, in the ROS frame (REP 103: z up,
metres; :mod:`cga.export.frames`). A world is a tree of links under one root,
``building``:

* a **structure** link per storey (``floor0_structure``; ``structure`` for a massing
  grammar's shapes), fixed to the root, with one visual mesh per structure node (wall,
  slab, roof, stair, mass) and every node's convex pieces as colliders
  (:func:`cga.collision.structure_pieces`: boxes where they are boxes). One link per
  storey rather than per node keeps a building under pybullet's 128 links per body;
* a **door** link per door leaf on a revolute joint at its hinge (:mod:`cga.doors`):
  axis up or down so that a positive angle opens the leaf into its swing room, limits
  ``0`` .. :attr:`~cga.doors.DoorLeaf.upper`, the build's angle as the joint's
  ``position``; the leaf collides through its box;
* an **item** link per furniture item: movable items on a floating joint (or fixed, as
  asked) with their mass, box inertia about their centre of mass and their convex parts
  shrunk for Bullet's margin (:func:`cga.collision.shrink_part`); static details
  (window frames, rugs) fixed and visual only, as the physics check sees them.

Link frames: a structure link's frame is the world's; a door link's is its hinge frame
with the leaf closed (x along the leaf towards the latch, z up); an item's sits at its
centre of mass turned by the item's yaw, so a simulator reports the item's pose directly.
Visual meshes and colliders are given in their link's frame.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Literal

import numpy as np

from cga.appearance.material import Material
from cga.collision import ConvexPiece, collision_parts, shrink_part, structure_pieces
from cga.errors import ExportError
from cga.scene import MeshArrays, Scene, SceneNode

from .frames import WORLD_TO_ROS, RosPose, pose_to_ros, world_to_ros
from .obj import MeshGroup, mesh_groups

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

__all__ = ["Box", "Collider", "Link", "Joint", "World", "robot_world", "box_inertia",
           "centre_of_mass", "identifier", "ItemJoints"]

ItemJoints = Literal["floating", "fixed"]
"""How items hang in a one-file world: free bodies (``floating``) or welded (``fixed``)."""

ROOT = "building"
"""Name of the root link every other link hangs from."""


@dataclass(frozen=True)
class Box:
    """A box collider: ``centre`` and full ``extents`` in its link frame, turned by
    ``yaw`` (rad) about the link's z axis."""

    centre: tuple[float, float, float]
    extents: tuple[float, float, float]
    yaw: float = 0.0


@dataclass(frozen=True)
class Collider:
    """One collision shape of a link: a :class:`Box` or a convex mesh (link frame)."""

    name: str
    box: Box | None = None
    mesh: MeshGroup | None = None


@dataclass(frozen=True)
class Link:
    """A rigid body. ``pose`` places its frame in the world (ROS); ``com`` is its centre
    of mass in its own frame and ``inertia`` the diagonal (ixx, iyy, izz) about it, along
    the link's axes. ``role`` is ``structure``, ``door`` or ``item``; ``label`` its
    semantic class (node kind or model name) and ``node`` the scene node path."""

    name: str
    role: Literal["structure", "door", "item"]
    label: str
    node: str | None
    pose: RosPose
    visual: tuple[MeshGroup, ...]
    colliders: tuple[Collider, ...]
    mass: float = 0.0
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def movable(self) -> bool:
        return self.mass > 0.0


@dataclass(frozen=True)
class Joint:
    """How ``child`` hangs from ``parent``: ``fixed``, ``floating`` or ``revolute``
    (about ``axis``, in the child's frame, from ``lower`` to ``upper`` rad; ``position``
    is the build's angle). The child's frame at position 0 is its link ``pose``."""

    name: str
    kind: Literal["fixed", "floating", "revolute"]
    parent: str
    child: str
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    lower: float = 0.0
    upper: float = 0.0
    position: float = 0.0
    state: str | None = None


@dataclass(frozen=True)
class World:
    """A build as links and joints (ROS frame), with its materials by name (the glb's,
    :mod:`cga.appearance`)."""

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    materials: dict[str, Material] = field(default_factory=dict)

    def link(self, name: str) -> Link:
        return next(link for link in self.links if link.name == name)

    def joint_of(self, link: str) -> Joint:
        return next(joint for joint in self.joints if joint.child == link)


def box_inertia(mass: float, extents: Sequence[float]) -> tuple[float, float, float]:
    """Principal moments (ixx, iyy, izz) of a solid box of ``mass`` kg and ``extents``
    (x, y, z) metres about its centre: m(b² + c²)/12 and permutations."""
    a, b, c = (float(e) for e in extents)
    return (mass * (b * b + c * c) / 12.0, mass * (a * a + c * c) / 12.0,
            mass * (a * a + b * b) / 12.0)


def centre_of_mass(parts: "Sequence[MeshArrays | trimesh.Trimesh]",
                   closed: Sequence[bool] | None = None) -> np.ndarray:
    """World centre of mass of solid convex parts of uniform density (the volume-weighted
    mean of their centroids); the bounding-box centre if they enclose no volume.

    ``closed`` says of each part whether it encloses a volume (trimesh's ``is_volume``;
    a part that does not stands for its convex hull), where that is known already: an
    item's parts are its model's turned and scaled, which keeps it
    (:attr:`ModelGeometry.closed_parts`), and testing it is most of the cost."""
    import trimesh

    if closed is None:
        closed = [trimesh.Trimesh(vertices=p.vertices, faces=p.faces, process=False).is_volume
                  for p in parts]
    volumes, centres = [], []
    for part, is_closed in zip(parts, closed):
        if is_closed:  # what Trimesh.mass_properties computes, without the Trimesh
            mass = trimesh.triangles.mass_properties(
                np.asarray(part.vertices, dtype=np.float64)[np.asarray(part.faces)],
                skip_inertia=True)
        else:
            mass = trimesh.Trimesh(vertices=part.vertices, faces=part.faces,
                                   process=False).convex_hull.mass_properties
        volumes.append(max(float(mass.volume), 0.0))
        centres.append(mass.center_mass)
    if sum(volumes) <= 0.0:
        bounds = np.array([trimesh.Trimesh(vertices=p.vertices, faces=p.faces,
                                           process=False).bounds for p in parts])
        return (bounds[:, 0].min(axis=0) + bounds[:, 1].max(axis=0)) / 2
    return np.average(centres, axis=0, weights=np.array(volumes))


def identifier(text: str) -> str:
    """``text`` as a name every format accepts (letters, digits, ``_``)."""
    name = re.sub(r"[^A-Za-z0-9_]+", "_", text).strip("_") or "item"
    return name if not name[0].isdigit() else f"n{name}"


def _unique(names: list[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for name in names:
        count = seen.get(name, 0) + 1
        seen[name] = count
        out.append(name if count == 1 else f"{name}_{count}")
    return out


class _Frame:
    """A link frame in ROS coordinates: world points → link coordinates."""

    def __init__(self, pose: RosPose):
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        self.rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        self.origin = np.asarray(pose.position, dtype=float)
        self.yaw = pose.yaw

    def local(self, world_points: np.ndarray) -> np.ndarray:
        # a ROS point p has link coordinates Rᵀ (p − origin), i.e. (p − origin) @ R as rows
        return (world_to_ros(world_points) - self.origin) @ self.rotation

    def visual(self, node: SceneNode, label: str, vertices: np.ndarray | None = None
               ) -> tuple[list[MeshGroup], dict[str, Material]]:
        """The node's visual groups in this frame (one per material) and their materials."""
        points = np.asarray(node.mesh.vertices if vertices is None else vertices, dtype=float)
        return mesh_groups(node, label, self.local(points))

    def collider(self, name: str, piece: ConvexPiece) -> Collider:
        if piece.box is not None:
            centre, extents, yaw = piece.box
            x, y, z = (float(v) for v in self.local(centre))
            # ROS x, y, z extents are world x, z, y; a turn about world +y is one about
            # ROS +z by the same angle (frames.py)
            return Collider(name, box=Box((x, y, z), (float(extents[0]), float(extents[2]),
                                                      float(extents[1])), yaw - self.yaw))
        return Collider(name, mesh=MeshGroup(name, self.local(piece.vertices),
                                             np.asarray(piece.faces), "collision"))


def _structure_link(nodes: Sequence[SceneNode], name: str) -> tuple[Link, dict[str, Material]]:
    """One fixed link for the structure of a storey: each node's visual meshes (named by
    the node, one per material) and every node's convex pieces."""
    frame = _Frame(RosPose((0.0, 0.0, 0.0), 0.0))
    visuals: list[MeshGroup] = []
    colliders: list[Collider] = []
    materials: dict[str, Material] = {}
    for node in nodes:
        label = identifier(node.path)
        groups, used = frame.visual(node, node.path)
        visuals.extend(groups)
        materials.update(used)
        colliders += [frame.collider(f"{label}_c{k}", piece)
                      for k, piece in enumerate(structure_pieces(node))]
    return (Link(name, "structure", "structure", None, frame_pose(frame), tuple(visuals),
                 tuple(colliders)), materials)


def _storey(node: SceneNode) -> str:
    """The structure link a node belongs to: ``floor{i}_structure`` for a storey's solids
    (paths ``floor{i}/...``), ``structure`` for the rest (masses, faces)."""
    head = node.path.split("/", 1)[0]
    return f"{head}_structure" if re.fullmatch(r"floor\d+", head) else "structure"


def frame_pose(frame: _Frame) -> RosPose:
    x, y, z = (float(v) for v in frame.origin)
    return RosPose((x, y, z), frame.yaw)


def _door_link(node: SceneNode, name: str) -> tuple[Link, Joint, dict[str, Material]]:
    leaf = node.door
    assert leaf is not None
    closed = leaf.frame(0.0)
    along = world_to_ros(closed[:3, 0])
    pose = pose_to_ros(closed[:3, 3])
    pose = RosPose(pose.position, math.atan2(float(along[1]), float(along[0])))
    frame = _Frame(pose)
    # the node's mesh stands at the build's angle: bring it back to the closed leaf
    undo = closed @ np.linalg.inv(leaf.frame())
    vertices = np.asarray(node.mesh.vertices, dtype=float) @ undo[:3, :3].T + undo[:3, 3]
    visual, used = frame.visual(node, name, vertices)
    centre, extents = leaf.box()
    box_world = closed[:3, :3] @ centre + closed[:3, 3]
    x, y, z = (float(v) for v in frame.local(box_world))
    # hinge frame x is the link's x; its y (up) is the link's z; its z is the link's −y
    box = Box((x, y, z), (float(extents[0]), float(extents[2]), float(extents[1])))
    density = node.item.density if node.item is not None else 500.0
    mass = float(np.prod(extents)) * density
    ixx, iyy, izz = box_inertia(mass, box.extents)
    link = Link(name, "door", "door", node.path, pose, tuple(visual),
                (Collider(f"{name}_c0", box=box),), mass=mass, com=(x, y, z),
                inertia=(ixx, iyy, izz))
    joint = Joint(f"{name}_hinge", "revolute", ROOT, name, axis=(0.0, 0.0, leaf.axis[1]),
                  lower=leaf.lower, upper=leaf.upper, position=leaf.angle, state=leaf.state)
    return link, joint, used


def _item_link(node: SceneNode, name: str) -> tuple[Link, Joint, dict[str, Material]]:
    """An item's link on a floating joint (a static one's on a fixed joint)."""
    item = node.item
    turns = item.rotation % 4 if item is not None else 0
    label = identifier(item.model if item is not None else "item")
    parts: list[MeshArrays | trimesh.Trimesh] = [
        *(collision_parts(node) if not node.static else node.parts or (node.mesh,))]
    frame = _Frame(pose_to_ros(centre_of_mass(parts, _closed_parts(node, parts)), 90.0 * turns))
    visual, used = frame.visual(node, label)
    material = visual[0].material if visual else "collision"
    if node.static:  # details and rugs: seen, not touched (the checks ignore them too)
        link = Link(name, "item", label, node.path, frame_pose(frame), tuple(visual), ())
        return link, Joint(f"{name}_joint", "fixed", ROOT, name), used
    mass = item.mass if item is not None else 0.0
    if not mass > 0.0:
        raise ExportError(f"furniture node '{node.path}' has no positive mass "
                          f"(got {mass!r}); robot exports need the mass of every movable item")
    solids = [frame.local(np.asarray(p.vertices, dtype=float)) for p in parts]
    colliders = tuple(
        Collider(f"{name}_c{k}", mesh=MeshGroup(f"{label}_part{k}", shrink_part(v),
                                                 np.asarray(p.faces), material))
        for k, (p, v) in enumerate(zip(parts, solids)))
    stacked = np.vstack(solids)
    link = Link(name, "item", label, node.path, frame_pose(frame), tuple(visual), colliders,
                mass=mass, inertia=box_inertia(mass, stacked.max(axis=0) - stacked.min(axis=0)))
    return link, Joint(f"{name}_joint", "floating", ROOT, name), used


def _closed_parts(node: SceneNode, parts: Sequence[object]) -> list[bool] | None:
    """Which of ``parts`` enclose a volume, when they are the node's model's parts
    (:func:`centre_of_mass`); None when that is not known."""
    item = node.item
    if item is None or item.geometry is None or not node.parts:
        return None
    kept = [closed for part, closed in zip(node.parts, item.geometry.closed_parts)
            if len(part.faces)]
    if len(kept) != len(parts) or any(a is not b for a, b in
                                       zip((p for p in node.parts if len(p.faces)), parts)):
        return None
    return kept


def robot_world(scene: Scene, nodes: Sequence[SceneNode], *,
                items: ItemJoints = "floating") -> World:
    """The build as one robot world (see the module notes), made once per build and
    nodes (:meth:`cga.scene.Scene.shared`): URDF, SDF, MJCF and USD are written from the
    same world, whose collision hulls and centres of mass are most of each one's cost.

    Parameters
    ----------
    scene:
        The build (its name names the world).
    nodes:
        Its scene nodes in world coordinates.
    items:
        How movable items hang from the root: ``floating`` (free bodies) or ``fixed``.

    Returns
    -------
    World
        Links after the root: one structure link per storey, then doors and items in
        node order, named after their node paths (``floor0/room1_Livingroom/furniture/sofa`` →
        ``floor0_room1_Livingroom_sofa``).

    Raises
    ------
    ExportError
        There is no static structure, or a movable item has no positive ``mass`` extra.
    """
    _, world = scene.shared(("robot_world", id(nodes)), lambda: (nodes, _robot_world(scene, nodes)))
    if items == "floating":
        return world
    return replace(world, joints=tuple(replace(j, kind=items) if j.kind == "floating" else j
                                       for j in world.joints))


def _robot_world(scene: Scene, nodes: Sequence[SceneNode]) -> World:
    """:func:`robot_world` with floating items, made afresh."""
    structure = [n for n in nodes if n.kind != "furniture" and len(n.mesh.faces)]
    if not structure:
        raise ExportError(f"robot export of '{scene.name}': the scene has no building "
                          f"geometry (walls, slabs or masses) to put in the world")
    root = Link(ROOT, "structure", "building", None, RosPose((0.0, 0.0, 0.0), 0.0), (), ())
    links, joints = [root], []
    materials: dict[str, Material] = {}
    storeys: dict[str, list[SceneNode]] = {}
    for node in structure:
        storeys.setdefault(_storey(node), []).append(node)
    for name, members in storeys.items():
        link, colours = _structure_link(members, name)
        links.append(link)
        joints.append(Joint(f"{name}_joint", "fixed", ROOT, name))
        materials.update(colours)
    furniture = [n for n in nodes if n.kind == "furniture" and len(n.mesh.faces)]
    names = _unique([identifier(n.path.replace("/furniture/", "/")) for n in furniture])
    for node, name in zip(furniture, names):
        if node.door is not None:
            link, joint, colours = _door_link(node, name)
        else:
            link, joint, colours = _item_link(node, name)
        links.append(link)
        joints.append(joint)
        materials.update(colours)
    return World(scene.name, tuple(links), tuple(joints), materials)


def world_points(points: np.ndarray) -> np.ndarray:
    """ROS points back in the world frame (y up)."""
    return np.asarray(points, dtype=float) @ WORLD_TO_ROS
