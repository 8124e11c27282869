"""URDF output: one URDF for the static building, one per furniture item, and an index.

Files (ROS frame, REP 103: z up, metres; see :mod:`cga.export.frames`):

* ``urdf/<name>.building.urdf``: one fixed link (mass 0) whose visual and collision
  meshes are in world coordinates; the collision mesh is marked ``concave="yes"`` so
  pybullet keeps it as a static triangle mesh instead of its convex hull.
* ``urdf/<name>.<item>.urdf``: one link per item with its inertial (mass from the
  node's ``mass`` extra, inertia of its box), visual mesh and one collision element per
  convex part, all relative to the link frame (see :mod:`cga.export.bodies`).
* ``<name>.urdf.json``: every body with its URDF path and base pose, so
  ``loadURDF(urdf, base_position, base_orientation_xyzw, useFixedBase=fixed)`` puts it
  where it stands.

Meshes live in ``meshes/`` beside ``urdf/`` and are referenced as ``../meshes/...``.
Fixed bodies also carry ``<gazebo><static>true</static></gazebo>`` for Gazebo.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .bodies import BodyFiles, RobotBody, numbers_text, write_bodies

__all__ = ["URDF_DIR", "body_as_urdf", "export_urdf"]

URDF_DIR = "urdf"
"""Folder (relative to the output folder) holding the URDF files."""


def _mesh(parent: ET.Element, filename: str) -> None:
    geometry = ET.SubElement(parent, "geometry")
    ET.SubElement(geometry, "mesh", filename=filename)


def body_as_urdf(body: RobotBody, files: BodyFiles, *, mesh_prefix: str = "../") -> str:
    """The URDF document of one body.

    Parameters
    ----------
    body:
        The body (link frame, meshes, mass).
    files:
        Its mesh files relative to the output folder.
    mesh_prefix:
        Prefix turning those paths into paths relative to the URDF file.

    Returns
    -------
    str
        URDF XML text.
    """
    robot = ET.Element("robot", name=body.name)
    link = ET.SubElement(robot, "link", name=body.name)
    inertial = ET.SubElement(link, "inertial")
    ET.SubElement(inertial, "origin", xyz="0 0 0", rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=numbers_text([body.mass]))
    ixx, iyy, izz = numbers_text(body.inertia).split()
    ET.SubElement(inertial, "inertia", ixx=ixx, ixy="0", ixz="0", iyy=iyy, iyz="0", izz=izz)
    visual = ET.SubElement(link, "visual", name=f"{body.name}_visual")
    ET.SubElement(visual, "origin", xyz="0 0 0", rpy="0 0 0")
    _mesh(visual, mesh_prefix + files.visual)
    material = ET.SubElement(visual, "material", name=f"{body.name}_material")
    ET.SubElement(material, "color", rgba=numbers_text([*body.color, 1.0]))
    for k, path in enumerate(files.collisions):
        attributes = {"name": f"{body.name}_collision{k}"}
        if body.concave:
            attributes["concave"] = "yes"
        collision = ET.SubElement(link, "collision", attributes)
        ET.SubElement(collision, "origin", xyz="0 0 0", rpy="0 0 0")
        _mesh(collision, mesh_prefix + path)
    if body.static:
        gazebo = ET.SubElement(robot, "gazebo")
        ET.SubElement(gazebo, "static").text = "true"
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def _index_entry(body: RobotBody, urdf_path: str) -> dict[str, object]:
    return {
        "name": body.name,
        "node": body.node,
        "urdf": urdf_path,
        "fixed": body.static,
        "mass": round(body.mass, 6),
        "base_position": [round(v, 6) + 0.0 for v in body.pose.position],
        "base_orientation_xyzw": [round(v, 9) + 0.0 for v in body.pose.quaternion_xyzw],
        "yaw": round(body.pose.yaw, 9) + 0.0,
    }


def export_urdf(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write the building and item URDFs, their meshes and ``<name>.urdf.json``.

    Raises
    ------
    ExportError
        See :func:`cga.export.bodies.write_bodies`.
    """
    out = Path(out_dir)
    bodies, files = write_bodies(scene, nodes, out, name)
    written, index = [], []
    for body in bodies:
        relative = f"{URDF_DIR}/{name}.{body.name}.urdf"
        written.append(atomic_write(out / relative, body_as_urdf(body, files[body.name])))
        index.append(_index_entry(body, relative))
    document = {
        "frame": "ROS REP 103 world frame: x, y horizontal, z up, metres; (x, y, z) = "
                 "(x, -z, y) of the scene JSON's world frame; the map frame of the "
                 f"{name}.floorN.yaml occupancy maps",
        "bodies": index,
    }
    written.append(atomic_write(out / f"{name}.urdf.json",
                                json.dumps(document, indent=2, sort_keys=True) + "\n"))
    return written + list(dict.fromkeys(
        out / f for body in bodies for f in files[body.name].paths()))
