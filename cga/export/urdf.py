"""URDF output: the whole building as one URDF, plus one URDF per movable item.

Files (ROS frame, REP 103: z up, metres; the world of :mod:`cga.export.world`):

* ``<name>.urdf``: one robot, ``<name>``, rooted at the link ``building``: every
  structure node a link on a fixed joint, every door leaf a link on a revolute joint at
  its hinge (limits from its swing, zero = closed), every item a link on a fixed joint
  (``robot_state_publisher``, RViz and Isaac Sim's URDF importer take one tree). Load it
  with ``useFixedBase``; the doors' build angles are in ``<name>.urdf.json``.
* ``urdf/<name>.building.urdf``: the building without its items, and
  ``urdf/<name>.<item>.urdf``: one link per item with its inertial (mass from the model,
  inertia of its box about its centre of mass), visual mesh and one collision element
  per convex part, relative to the link frame. For simulators that want the items as
  free bodies.
* ``<name>.urdf.json``: every body file with its base pose, so
  ``loadURDF(urdf, base_position, base_orientation_xyzw, useFixedBase=fixed)`` puts it
  where it stands, and every door joint with its state and angle.

Colliders are boxes (``<box>``) or convex OBJ meshes, never a concave mesh: every URDF
reader can use them as they are. Meshes live in ``meshes/`` beside the files.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .bodies import LinkFiles, numbers_text, write_link_meshes
from .world import ROOT, ItemJoints, Joint, Link, World, robot_world

__all__ = ["URDF_DIR", "world_as_urdf", "export_urdf"]

URDF_DIR = "urdf"
"""Folder (relative to the output folder) holding the per-body URDF files."""


def _origin(parent: ET.Element, xyz: Sequence[float], yaw: float = 0.0) -> None:
    ET.SubElement(parent, "origin", xyz=numbers_text(xyz), rpy=numbers_text([0.0, 0.0, yaw]))


def _link(robot: ET.Element, link: Link, files: LinkFiles, prefix: str,
          color: Sequence[float]) -> None:
    element = ET.SubElement(robot, "link", name=link.name)
    # fixed links get mass 0 explicitly: without an inertial, pybullet gives a link 1 kg
    # and warns
    inertial = ET.SubElement(element, "inertial")
    _origin(inertial, link.com)
    ET.SubElement(inertial, "mass", value=numbers_text([link.mass]))
    ixx, iyy, izz = numbers_text(link.inertia).split()
    ET.SubElement(inertial, "inertia", ixx=ixx, ixy="0", ixz="0", iyy=iyy, iyz="0", izz=izz)
    if files.visual is not None:
        visual = ET.SubElement(element, "visual", name=f"{link.name}_visual")
        _origin(visual, (0.0, 0.0, 0.0))
        ET.SubElement(ET.SubElement(visual, "geometry"), "mesh", filename=prefix + files.visual)
        material = ET.SubElement(visual, "material", name=f"{link.name}_material")
        ET.SubElement(material, "color", rgba=numbers_text(color))
    for collider in link.colliders:
        collision = ET.SubElement(element, "collision", name=collider.name)
        geometry_parent = collision
        if collider.box is not None:
            _origin(collision, collider.box.centre, collider.box.yaw)
            ET.SubElement(ET.SubElement(geometry_parent, "geometry"), "box",
                          size=numbers_text(collider.box.extents))
        else:
            _origin(collision, (0.0, 0.0, 0.0))
            ET.SubElement(ET.SubElement(geometry_parent, "geometry"), "mesh",
                          filename=prefix + files.colliders[collider.name])


def _joint(robot: ET.Element, joint: Joint, child: Link) -> None:
    element = ET.SubElement(robot, "joint", name=joint.name, type=joint.kind)
    ET.SubElement(element, "parent", link=joint.parent)
    ET.SubElement(element, "child", link=joint.child)
    _origin(element, child.pose.position, child.pose.yaw)
    if joint.kind == "revolute":
        ET.SubElement(element, "axis", xyz=numbers_text(joint.axis))
        ET.SubElement(element, "limit", lower=numbers_text([joint.lower]),
                      upper=numbers_text([joint.upper]), effort="100", velocity="2")
        ET.SubElement(element, "dynamics", damping="2", friction="1")


def _document(robot: ET.Element) -> str:
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def world_as_urdf(world: World, files: dict[str, LinkFiles], *, robot_name: str | None = None,
                  links: Sequence[str] | None = None, mesh_prefix: str = "") -> str:
    """One URDF robot of the world's root and ``links`` (default: all of them).

    Parameters
    ----------
    world:
        The robot world.
    files:
        Its mesh files relative to the output folder.
    robot_name:
        The ``<robot name>``; default the world's name.
    links:
        Names of the links to include besides the root, with their joints.
    mesh_prefix:
        Prefix turning mesh paths into paths relative to the URDF file.
    """
    robot = ET.Element("robot", name=robot_name or world.name)
    chosen = [link for link in world.links
              if link.name == ROOT or links is None or link.name in links]
    for link in chosen:
        _link(robot, link, files[link.name], mesh_prefix, _color(world, link))
    for link in chosen:
        if link.name != ROOT:
            _joint(robot, world.joint_of(link.name), link)
    gazebo = ET.SubElement(robot, "gazebo", reference=ROOT)
    ET.SubElement(gazebo, "static").text = "true"
    return _document(robot)


def item_as_urdf(world: World, link: Link, files: LinkFiles, *, mesh_prefix: str = "../") -> str:
    """The URDF of one item as a robot of one link, in the item's own frame."""
    robot = ET.Element("robot", name=link.name)
    _link(robot, link, files, mesh_prefix, _color(world, link))
    if not link.movable:
        ET.SubElement(ET.SubElement(robot, "gazebo"), "static").text = "true"
    return _document(robot)


def _color(world: World, link: Link) -> tuple[float, float, float, float]:
    """The RGBA of a link's visual: its first material's (URDF has one colour per
    visual; the MTL beside the mesh has every material)."""
    material = world.materials.get(link.visual[0].material) if link.visual else None
    if material is None:
        return (0.8, 0.8, 0.8, 1.0)
    return (*material.color, material.alpha)


def _pose_entry(link: Link) -> dict[str, object]:
    return {
        "base_position": [round(v, 6) + 0.0 for v in link.pose.position],
        "base_orientation_xyzw": [round(v, 9) + 0.0 for v in link.pose.quaternion_xyzw],
        "yaw": round(link.pose.yaw, 9) + 0.0,
    }


def export_urdf(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str, *,
                items: ItemJoints = "fixed") -> list[Path]:
    """Write ``<name>.urdf``, the per-body URDFs, their meshes and ``<name>.urdf.json``.

    ``items`` is how the items hang in ``<name>.urdf``: ``"fixed"`` (``cga build``'s
    choice: one rigid tree, what ``robot_state_publisher`` and pybullet handle) or
    ``"floating"`` (URDF floating joints, for importers that make them free bodies).

    Raises
    ------
    ExportError
        See :func:`cga.export.world.robot_world`.
    """
    out = Path(out_dir)
    world = robot_world(scene, nodes, items=items)
    files = write_link_meshes(scene, world, out, name)
    written = [atomic_write(out / f"{name}.urdf", world_as_urdf(world, files))]
    building = [link.name for link in world.links if link.role != "item"]
    relative = f"{URDF_DIR}/{name}.building.urdf"
    written.append(atomic_write(out / relative, world_as_urdf(
        world, files, robot_name="building", links=building, mesh_prefix="../")))
    index: list[dict[str, object]] = [{"name": ROOT, "node": None, "urdf": relative,
                                       "fixed": True, "mass": 0.0,
                                       **_pose_entry(world.link(ROOT))}]
    for link in world.links:
        if link.role != "item":
            continue
        relative = f"{URDF_DIR}/{name}.{link.name}.urdf"
        written.append(atomic_write(out / relative, item_as_urdf(world, link, files[link.name])))
        index.append({"name": link.name, "node": link.node, "urdf": relative,
                      "fixed": not link.movable, "mass": round(link.mass, 6),
                      **_pose_entry(link)})
    doors = [{"joint": j.name, "link": j.child, "node": world.link(j.child).node,
              "state": j.state, "position": round(j.position, 9), "lower": j.lower,
              "upper": round(j.upper, 9), "axis": list(j.axis)}
             for j in world.joints if j.kind == "revolute"]
    document = {
        "frame": "ROS REP 103 world frame: x, y horizontal, z up, metres; (x, y, z) = "
                 "(x, -z, y) of the scene JSON's world frame; the map frame of the "
                 f"{name}.floorN.yaml occupancy maps",
        "world": f"{name}.urdf",
        "bodies": index,
        "doors": doors,
    }
    written.append(atomic_write(out / f"{name}.urdf.json",
                                json.dumps(document, indent=2, sort_keys=True) + "\n"))
    return written + list(dict.fromkeys(
        out / f for link in world.links for f in files[link.name].paths()))
