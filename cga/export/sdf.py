"""SDF world output, ``<name>.world.sdf`` (SDFormat 1.7): the building with hinged doors,
and every item.

The world (:mod:`cga.export.world`, ROS frame: z up, metres) holds

* one static model ``building``: a link ``structure`` with every structure node's visual
  and colliders (boxes, convex meshes), and a link per door leaf on a ``revolute`` joint
  to it at its hinge (axis, limits, damping). pybullet's ``loadSDF`` makes a static
  model a fixed-base body whose joints still turn (it does not know joints to
  ``world``, the other way to hold a structure in place); Gazebo keeps a static model's
  links where they are, so there the leaves stand closed;
* one model per item with its pose and a link with inertial, visual and collision
  elements (static for details and rugs, which carry no collision, as in the checks).

Only standard SDFormat elements are written (no reader-specific attributes), so
``gz sdf -k`` / ``ign sdf -k`` validate it; meshes are referenced by URI relative to the
world file (``meshes/...``, the files the URDFs use), which Gazebo and pybullet's
``loadSDF`` resolve against the file's folder. SDFormat has no initial joint position:
doors start closed; their build angles are in ``<name>.urdf.json`` and the scene JSON.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .bodies import LinkFiles, numbers_text, write_link_meshes
from .world import ROOT, Link, World, robot_world

__all__ = ["SDF_VERSION", "world_as_sdf", "export_sdf"]

SDF_VERSION = "1.7"

STRUCTURE = "structure"
"""Name of the building model's structure link, the parent of its doors."""


def _pose(parent: ET.Element, xyz: Sequence[float], yaw: float = 0.0) -> None:
    ET.SubElement(parent, "pose").text = numbers_text([*xyz, 0.0, 0.0, yaw])


def _inertial(link: ET.Element, source: Link | None) -> None:
    """The inertial of a movable link, or (``None``) a unit placeholder for a welded or
    static one: Gazebo ignores it, and without one pybullet's SDF reader warns."""
    inertial = ET.SubElement(link, "inertial")
    _pose(inertial, source.com if source else (0.0, 0.0, 0.0))
    ET.SubElement(inertial, "mass").text = numbers_text([source.mass if source else 1.0])
    inertia = ET.SubElement(inertial, "inertia")
    for key, value in zip(("ixx", "iyy", "izz"), source.inertia if source else (1.0,) * 3):
        ET.SubElement(inertia, key).text = numbers_text([value])
    for key in ("ixy", "ixz", "iyz"):
        ET.SubElement(inertia, key).text = "0"


def _geometry(parent: ET.Element, source: Link, files: LinkFiles, world: World) -> None:
    """Visual and collision elements of ``source`` into the SDF link ``parent``."""
    if files.visual is not None:
        visual = ET.SubElement(parent, "visual", name=f"{source.name}_visual")
        mesh = ET.SubElement(ET.SubElement(visual, "geometry"), "mesh")
        ET.SubElement(mesh, "uri").text = files.visual
        material = ET.SubElement(visual, "material")
        look = world.materials.get(source.visual[0].material)
        rgba = numbers_text([*look.color, look.alpha] if look is not None
                            else [0.8, 0.8, 0.8, 1.0])
        ET.SubElement(material, "ambient").text = rgba
        ET.SubElement(material, "diffuse").text = rgba
    for collider in source.colliders:
        collision = ET.SubElement(parent, "collision", name=collider.name)
        if collider.box is not None:
            _pose(collision, collider.box.centre, collider.box.yaw)
            box = ET.SubElement(ET.SubElement(collision, "geometry"), "box")
            ET.SubElement(box, "size").text = numbers_text(collider.box.extents)
        else:
            mesh = ET.SubElement(ET.SubElement(collision, "geometry"), "mesh")
            ET.SubElement(mesh, "uri").text = files.colliders[collider.name]


def _building(world_el: ET.Element, world: World, files: dict[str, LinkFiles]) -> None:
    model = ET.SubElement(world_el, "model", name=ROOT)
    ET.SubElement(model, "static").text = "1"
    _pose(model, (0.0, 0.0, 0.0))
    structure = ET.SubElement(model, "link", name=STRUCTURE)
    _inertial(structure, None)
    for link in world.links:
        if link.role == "structure" and link.name != ROOT:
            _geometry(structure, link, files[link.name], world)
    for joint in world.joints:
        if joint.kind != "revolute":
            continue
        leaf = world.link(joint.child)
        leaf_element = ET.SubElement(model, "link", name=leaf.name)
        _pose(leaf_element, leaf.pose.position, leaf.pose.yaw)
        _inertial(leaf_element, leaf)
        _geometry(leaf_element, leaf, files[leaf.name], world)
        element = ET.SubElement(model, "joint", name=joint.name, type="revolute")
        ET.SubElement(element, "parent").text = STRUCTURE
        ET.SubElement(element, "child").text = leaf.name
        axis = ET.SubElement(element, "axis")
        ET.SubElement(axis, "xyz").text = numbers_text(joint.axis)
        limit = ET.SubElement(axis, "limit")
        ET.SubElement(limit, "lower").text = numbers_text([joint.lower])
        ET.SubElement(limit, "upper").text = numbers_text([joint.upper])
        dynamics = ET.SubElement(axis, "dynamics")
        ET.SubElement(dynamics, "damping").text = "2"
        ET.SubElement(dynamics, "friction").text = "1"


def _item(world_el: ET.Element, link: Link, files: LinkFiles, world: World) -> None:
    model = ET.SubElement(world_el, "model", name=link.name)
    # "1"/"0" rather than "true"/"false": pybullet's SDF reader only understands digits
    ET.SubElement(model, "static").text = "0" if link.movable else "1"
    _pose(model, link.pose.position, link.pose.yaw)
    element = ET.SubElement(model, "link", name="link")
    _inertial(element, link if link.movable else None)
    _geometry(element, link, files, world)


def world_as_sdf(world: World, files: dict[str, LinkFiles]) -> str:
    """The SDF document of ``world`` (mesh paths from ``files``)."""
    root = ET.Element("sdf", version=SDF_VERSION)
    world_el = ET.SubElement(root, "world", name=world.name)
    ET.SubElement(world_el, "gravity").text = "0 0 -9.81"
    sun = ET.SubElement(world_el, "light", name="sun", type="directional")
    ET.SubElement(sun, "cast_shadows").text = "true"
    _pose(sun, (0.0, 0.0, 20.0))
    ET.SubElement(sun, "diffuse").text = "0.9 0.9 0.9 1"
    ET.SubElement(sun, "direction").text = "-0.4 0.3 -1"
    _building(world_el, world, files)
    for link in world.links:
        if link.role == "item":
            _item(world_el, link, files[link.name], world)
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def export_sdf(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<name>.world.sdf`` and the meshes it refers to.

    Raises
    ------
    ExportError
        See :func:`cga.export.world.robot_world`.
    """
    out = Path(out_dir)
    world = robot_world(scene, nodes)
    files = write_link_meshes(scene, world, out, name)
    written = atomic_write(out / f"{name}.world.sdf", world_as_sdf(world, files))
    return [written] + list(dict.fromkeys(
        out / f for link in world.links for f in files[link.name].paths()))
