"""Sensor data: camera views, depth, semantic and instance masks of a build (DESIGN §15).

* :mod:`.inputs`: what a render needs, from a :class:`~cga.scene.Scene` or read back from
  a build's scene JSON and glb;
* :mod:`.placement`: the cameras, seeded in the reachable free space of every room, and
  the top-down camera of each floor on its ROS map's grid;
* :mod:`.cameras`: intrinsics, extrinsics (OpenCV and glTF conventions), pixel rays;
* :mod:`.raycast`: one Embree ray cast per pixel, labels per triangle;
* :mod:`.shading`: the colour image;
* :mod:`.views`: a view's images and a build's views and maps;
* :mod:`.files`: ``<name>.render/`` (PNGs, camera JSON, ``index.json``).

docs/render.md describes the files and conventions.
"""

from __future__ import annotations

from .cameras import Camera
from .files import write_render
from .inputs import RenderInputs, inputs_from_files, inputs_from_scene
from .placement import RenderOptions
from .views import ViewImages, ViewRenderer, render_build

__all__ = ["Camera", "RenderInputs", "RenderOptions", "ViewImages", "ViewRenderer",
           "inputs_from_files", "inputs_from_scene", "render_build", "write_render"]
