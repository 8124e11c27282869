"""SDF world output, ``<name>.world.sdf`` (SDF 1.6): the building and every item.

The world holds one static ``building`` model and one model per furniture item, each
with its pose (ROS frame: z up, metres), a link with inertial, visual and collision
elements, and meshes referenced by URI relative to the world file (``meshes/...``, the
same files the URDFs use, see :mod:`cga.export.bodies`). pybullet's ``loadSDF`` returns
one body per model; Gazebo resolves the relative URIs against the world file's folder.

The building's collision carries ``concave="yes"``, pybullet's switch for keeping a
static mesh concave (other SDF readers ignore the attribute).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .bodies import BodyFiles, RobotBody, numbers_text, write_bodies

__all__ = ["SDF_VERSION", "world_as_sdf", "export_sdf"]

SDF_VERSION = "1.6"


def _geometry(parent: ET.Element, uri: str) -> None:
    mesh = ET.SubElement(ET.SubElement(parent, "geometry"), "mesh")
    ET.SubElement(mesh, "uri").text = uri


def _model(world: ET.Element, body: RobotBody, files: BodyFiles) -> None:
    model = ET.SubElement(world, "model", name=body.name)
    # "1"/"0" rather than "true"/"false": pybullet's SDF reader only understands digits
    ET.SubElement(model, "static").text = "1" if body.static else "0"
    ET.SubElement(model, "pose").text = numbers_text([*body.pose.position, *body.pose.rpy])
    link = ET.SubElement(model, "link", name="link")
    # Static models get an inertial too (Gazebo ignores it; without one pybullet's SDF
    # reader warns once per link): a unit mass, unit inertia placeholder.
    mass, inertia_diagonal = ((body.mass, body.inertia) if not body.static
                              else (1.0, (1.0, 1.0, 1.0)))
    inertial = ET.SubElement(link, "inertial")
    ET.SubElement(inertial, "pose").text = "0 0 0 0 0 0"
    ET.SubElement(inertial, "mass").text = numbers_text([mass])
    inertia = ET.SubElement(inertial, "inertia")
    for key, value in zip(("ixx", "iyy", "izz"), inertia_diagonal):
        ET.SubElement(inertia, key).text = numbers_text([value])
    for key in ("ixy", "ixz", "iyz"):
        ET.SubElement(inertia, key).text = "0"
    visual = ET.SubElement(link, "visual", name="visual")
    _geometry(visual, files.visual)
    material = ET.SubElement(visual, "material")
    rgba = numbers_text([*body.color, 1.0])
    ET.SubElement(material, "ambient").text = rgba
    ET.SubElement(material, "diffuse").text = rgba
    for k, uri in enumerate(files.collisions):
        attributes = {"name": f"collision{k}"}
        if body.concave:
            attributes["concave"] = "yes"
        _geometry(ET.SubElement(link, "collision", attributes), uri)


def world_as_sdf(world_name: str, bodies: Sequence[RobotBody],
                 files: dict[str, BodyFiles]) -> str:
    """The SDF document of a world holding ``bodies`` (mesh paths from ``files``)."""
    root = ET.Element("sdf", version=SDF_VERSION)
    world = ET.SubElement(root, "world", name=world_name)
    ET.SubElement(world, "gravity").text = "0 0 -9.81"
    sun = ET.SubElement(world, "light", name="sun", type="directional")
    ET.SubElement(sun, "cast_shadows").text = "true"
    ET.SubElement(sun, "pose").text = "0 0 20 0 0 0"
    ET.SubElement(sun, "diffuse").text = "0.9 0.9 0.9 1"
    ET.SubElement(sun, "direction").text = "-0.4 0.3 -1"
    for body in bodies:
        _model(world, body, files[body.name])
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def export_sdf(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<name>.world.sdf`` and the meshes it refers to.

    Raises
    ------
    ExportError
        See :func:`cga.export.bodies.write_bodies`.
    """
    out = Path(out_dir)
    bodies, files = write_bodies(scene, nodes, out, name)
    world = atomic_write(out / f"{name}.world.sdf", world_as_sdf(name, bodies, files))
    return [world] + list(dict.fromkeys(
        out / f for body in bodies for f in files[body.name].paths()))
