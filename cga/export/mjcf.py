"""MJCF output for MuJoCo, ``<name>.mjcf.xml``: one self-contained file per building.

The robot world (:mod:`cga.export.world`, ROS frame: z up, metres) becomes:

* the structure as static geoms of the world body: its convex pieces as ``box`` geoms
  (walls split around their openings, slabs) or convex ``mesh`` geoms, plus each node's
  visual mesh, which does not collide;
* each door leaf as a body at its hinge with a ``hinge`` joint (axis, ``range`` 0 ..
  open, damping and friction loss so it stays where it is put), its box collider and
  visual mesh; the body stands at the build's angle and the joint's ``ref`` is that
  angle, so ``qpos`` reads the door's angle (0 = closed) from the start;
* each movable item as a free body (``freejoint``) at its centre of mass, with its mass
  and box inertia, one convex ``mesh`` geom per collision part and a separate visual
  mesh; details (window frames, rugs) as fixed bodies that only show.

Meshes are written inline (``vertex``/``face`` attributes), so the file needs no others.
Visual geoms are in group 1 and collide with nothing; colliders are in group 3 (hidden
in the viewer by default). Materials carry the exports' colours.
"""

from __future__ import annotations

import hashlib
import math
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .bodies import numbers_text
from .obj import MeshGroup
from .world import ROOT, Collider, Joint, Link, World, robot_world

__all__ = ["world_as_mjcf", "export_mjcf"]

_VISUAL_GROUP, _COLLISION_GROUP = "1", "3"


def _quat(yaw: float) -> str:
    """MuJoCo's (w, x, y, z) quaternion of a turn by ``yaw`` about +z."""
    return numbers_text([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


class _Assets:
    """The ``<asset>`` element: materials, and meshes shared by content."""

    def __init__(self, root: ET.Element, world: World):
        self.element = ET.SubElement(root, "asset")
        self.meshes: dict[str, str] = {}
        for name, look in sorted(world.materials.items()):
            ET.SubElement(self.element, "material", name=name,
                          rgba=numbers_text([*look.color, look.alpha]),
                          specular=numbers_text([0.1 + 0.4 * look.metallic]),
                          shininess=numbers_text([round(1.0 - look.roughness, 3)]))
        ET.SubElement(self.element, "material", name="collision", rgba="0.9 0.3 0.3 0.4")

    def mesh(self, group: MeshGroup, *, visual: bool) -> str:
        """The name of a mesh asset with ``group``'s triangles (added once per content).
        Visual meshes use shell inertia, so open or thin ones compile too."""
        vertex = numbers_text(np.asarray(group.vertices, dtype=float).ravel())
        face = " ".join(str(int(i)) for i in np.asarray(group.faces).ravel())
        key = hashlib.sha1(f"{visual}|{vertex}|{face}".encode()).hexdigest()[:12]
        if key not in self.meshes:
            name = f"mesh_{key}"
            attributes = {"name": name, "vertex": vertex}
            if visual:
                attributes.update(face=face, inertia="shell")
            ET.SubElement(self.element, "mesh", attributes)
            self.meshes[key] = name
        return self.meshes[key]


def _colliders(body: ET.Element, link: Link, assets: _Assets) -> None:
    for collider in link.colliders:
        ET.SubElement(body, "geom", _collider_attributes(collider, assets))


def _collider_attributes(collider: Collider, assets: _Assets) -> dict[str, str]:
    attributes = {"name": collider.name, "group": _COLLISION_GROUP, "material": "collision"}
    if collider.box is not None:
        attributes.update(type="box", pos=numbers_text(collider.box.centre),
                          size=numbers_text(np.asarray(collider.box.extents) / 2),
                          quat=_quat(collider.box.yaw))
    else:
        assert collider.mesh is not None
        # a convex piece: MuJoCo collides with a mesh's convex hull, which is the piece
        attributes.update(type="mesh", mesh=assets.mesh(collider.mesh, visual=False))
    return attributes


def _visuals(body: ET.Element, link: Link, assets: _Assets) -> None:
    for k, group in enumerate(link.visual):
        ET.SubElement(body, "geom", name=f"{link.name}_visual{k}", type="mesh",
                      mesh=assets.mesh(group, visual=True), material=group.material,
                      group=_VISUAL_GROUP, contype="0", conaffinity="0")


def _inertial(body: ET.Element, link: Link) -> None:
    ET.SubElement(body, "inertial", pos=numbers_text(link.com), mass=numbers_text([link.mass]),
                  diaginertia=numbers_text(np.maximum(link.inertia, 1e-9)))


def _door(worldbody: ET.Element, link: Link, joint: Joint, assets: _Assets) -> None:
    # the body stands at the build's angle; ref makes qpos read that angle there
    yaw = link.pose.yaw + joint.axis[2] * joint.position
    body = ET.SubElement(worldbody, "body", name=link.name, pos=numbers_text(link.pose.position),
                         quat=_quat(yaw))
    ET.SubElement(body, "joint", name=joint.name, type="hinge", axis=numbers_text(joint.axis),
                  range=numbers_text([joint.lower, joint.upper]),
                  ref=numbers_text([joint.position]), damping="2", frictionloss="1",
                  armature="0.01")
    _inertial(body, link)
    _colliders(body, link, assets)
    _visuals(body, link, assets)


def _item(worldbody: ET.Element, link: Link, assets: _Assets) -> None:
    body = ET.SubElement(worldbody, "body", name=link.name, pos=numbers_text(link.pose.position),
                         quat=_quat(link.pose.yaw))
    if link.movable:
        ET.SubElement(body, "freejoint", name=f"{link.name}_free")
        _inertial(body, link)
    _colliders(body, link, assets)
    _visuals(body, link, assets)


def world_as_mjcf(world: World) -> str:
    """The MJCF document of ``world``."""
    root = ET.Element("mujoco", model=world.name)
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    ET.SubElement(root, "option", timestep="0.002", gravity="0 0 -9.81", cone="elliptic",
                  integrator="implicitfast")
    visual = ET.SubElement(root, "visual")
    ET.SubElement(visual, "headlight", ambient="0.4 0.4 0.4", diffuse="0.6 0.6 0.6")
    assets = _Assets(root, world)
    worldbody = ET.SubElement(root, "worldbody")
    ET.SubElement(worldbody, "light", name="sun", pos="0 0 20", dir="-0.4 0.3 -1",
                  directional="true")
    for link in world.links:
        if link.name == ROOT:
            continue
        if link.role == "structure":
            _colliders(worldbody, link, assets)
            _visuals(worldbody, link, assets)
        elif link.role == "door":
            _door(worldbody, link, world.joint_of(link.name), assets)
        else:
            _item(worldbody, link, assets)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def export_mjcf(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<name>.mjcf.xml``.

    Raises
    ------
    ExportError
        See :func:`cga.export.world.robot_world`.
    """
    world = robot_world(scene, nodes)
    return [atomic_write(Path(out_dir) / f"{name}.mjcf.xml", world_as_mjcf(world))]
