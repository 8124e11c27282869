"""Mesh files of a robot world (:mod:`cga.export.world`), shared by URDF and SDF.

:func:`write_link_meshes` writes, under ``meshes/`` next to the world file, one visual OBJ
per link and one OBJ per convex-mesh collider (box colliders are primitives in the XML),
all in their link's frame (ROS axes, metres), plus one MTL with every material. Files are
named by the link's label and a hash of their content, so items with equal meshes in
their own frames share files, and the URDF and SDF exporters share them in one folder.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING
from pathlib import Path

import numpy as np

from cga.fsutil import atomic_write

from .obj import mtl_text, obj_text
from .world import World

if TYPE_CHECKING:  # pragma: no cover
    from cga.scene import Scene

__all__ = ["MESH_DIR", "LinkFiles", "write_link_meshes", "numbers_text"]

MESH_DIR = "meshes"
"""Folder (relative to the output folder) holding the robot exporters' OBJ files."""


@dataclass(frozen=True)
class LinkFiles:
    """Mesh files of a link, relative to the output folder (POSIX separators):
    ``visual`` (None for a link with nothing to show) and one file per collider name
    whose shape is a mesh."""

    visual: str | None
    material: str
    colliders: dict[str, str]

    def paths(self) -> list[str]:
        """Every file of the link."""
        return [p for p in (self.visual, self.material, *self.colliders.values()) if p]


def numbers_text(values: "Sequence[float] | np.ndarray") -> str:
    """Numbers as XML attribute/element text: space separated, at most 6 decimals."""
    out = []
    for value in values:
        text = f"{float(value) + 0.0:.6f}".rstrip("0").rstrip(".")
        out.append("0" if text in ("", "-0") else text)
    return " ".join(out)


def _write_once(folder: Path, stem: str, text: str) -> str:
    """Write ``text`` to ``<folder>/<stem>.<hash>.obj`` unless that file exists (the name
    is derived from the content, so an existing file is this one)."""
    digest = hashlib.sha1(text.encode("utf-8")).hexdigest()[:12]
    file_name = f"{stem}.{digest}.obj"
    if not (folder / file_name).is_file():
        atomic_write(folder / file_name, text)
    return f"{MESH_DIR}/{file_name}"


def write_link_meshes(scene: Scene, world: World, out_dir: Path, name: str) -> dict[str, LinkFiles]:
    """Write the world's visual and collision OBJs and one MTL under ``meshes/``.

    The OBJ texts are made once per build and world (:meth:`cga.scene.Scene.shared`):
    URDF and SDF write the same files, and making the text is most of writing them.

    Returns
    -------
    dict
        Link name → its files, relative to ``out_dir``.
    """
    folder = Path(out_dir) / MESH_DIR
    mtl_name = f"{name}.mtl"
    atomic_write(folder / mtl_name, mtl_text(world.materials))
    _, texts = scene.shared(("link meshes", id(world.links), name),
                            lambda: (world.links, _link_mesh_texts(world, mtl_name)))
    files: dict[str, LinkFiles] = {}
    for link in world.links:
        stem = f"{name}.{link.label}"
        visual, colliders = texts[link.name]
        files[link.name] = LinkFiles(
            None if visual is None else _write_once(folder, stem, visual),
            f"{MESH_DIR}/{mtl_name}",
            {c: _write_once(folder, f"{stem}.collision", text) for c, text in colliders.items()})
    return files


def _link_mesh_texts(world: World, mtl_name: str) -> dict[str, tuple[str | None, dict[str, str]]]:
    """Link name → the OBJ text of its visual (None: none) and of each convex-mesh
    collider by name."""
    header = "cga mesh: ROS frame axes (z up), metres, relative to its link's frame"
    return {link.name: (
        obj_text(link.visual, mtl_file=mtl_name, header=header) if link.visual else None,
        {c.name: obj_text([c.mesh], mtl_file=None, header=header + "; collision")
         for c in link.colliders if c.mesh is not None})
        for link in world.links}
