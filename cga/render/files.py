"""The files of a render: ``<name>.render/`` (docs/render.md).

Per view ``<view>.rgb.png`` (8-bit sRGB), ``<view>.depth.png`` (16-bit, millimetres along
the optical axis, 0 where nothing was hit or beyond 65.535 m), ``<view>.semantic.png``
and ``<view>.instance.png`` (16-bit ids) and ``<view>.camera.json``; per floor the maps
on the ROS map's grid, ``floor{N}.room_types.png``, ``floor{N}.instances.png``,
``floor{N}.semantic.png`` with ``floor{N}.maps.yaml`` (map_server's ``resolution`` and
``origin``); and ``index.json`` listing views, maps, rooms without a view, the classes
and the instances. Every file is written atomically and is a pure function of the
build and the options: the same seed gives byte-identical files (no timings inside).
"""

from __future__ import annotations

import io
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from cga.export.bodies import numbers_text
from cga.export.scene_json import json_text
from cga.fsutil import atomic_write
from cga.semantics import class_table

from .inputs import RenderInputs
from .placement import RenderOptions
from .views import FloorMaps, ViewImages, render_build

__all__ = ["FORMAT", "png_bytes", "depth_millimetres", "write_render", "render_folder"]

FORMAT = "cga.render"
"""The ``format`` of ``index.json``."""

_NEAR, _FAR = 0.01, 100.0
"""The glTF ``znear``/``zfar`` of the perspective cameras (m)."""

_PNG_LEVEL = 1
"""zlib level of the PNGs: fast to write; masks and depth compress well anyway."""


def render_folder(name: str) -> str:
    """The folder (relative to the output folder) a build's render goes to."""
    return f"{name}.render"


def png_bytes(image: np.ndarray) -> bytes:
    """A PNG of an ``uint8[h, w, 3]`` colour image or an ``uint16[h, w]`` grey one."""
    out = io.BytesIO()
    if image.dtype == np.uint16:
        picture = Image.fromarray(np.ascontiguousarray(image))  # mode I;16
    else:
        picture = Image.fromarray(np.ascontiguousarray(image, dtype=np.uint8))
    picture.save(out, format="PNG", compress_level=_PNG_LEVEL)
    return out.getvalue()


def depth_millimetres(depth: np.ndarray) -> np.ndarray:
    """``uint16`` millimetres of a depth image in metres; 0 where it is not finite, not
    positive or beyond 65.535 m."""
    mm = np.rint(np.where(np.isfinite(depth), depth, 0.0) * 1000.0)
    mm[(mm <= 0) | (mm > 65535)] = 0
    return mm.astype(np.uint16)


def _rounded(value: Any) -> Any:
    if isinstance(value, float):
        return round(value, 9) + 0.0
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_rounded(v) for v in value]
    return value


def _json(data: Any) -> str:
    return json_text(_rounded(data))


def _view_files(folder: Path, view: ViewImages) -> tuple[list[Path], dict[str, str]]:
    camera = view.camera
    names = {kind: f"{camera.name}.{kind}.png" for kind in ("rgb", "depth", "semantic", "instance")}
    names["camera"] = f"{camera.name}.camera.json"
    far = _FAR if not camera.orthographic else float(np.nanmax(
        np.where(np.isfinite(view.depth), view.depth, 0.0), initial=0.0)) + 1.0
    document = {**camera.to_dict(near=0.0 if camera.orthographic else _NEAR, far=far),
                "depth": {"file": names["depth"], "unit": "mm", "scale": 0.001, "invalid": 0,
                          "measure": "distance along the optical axis (z)"},
                "files": names}
    images = {"rgb": view.rgb, "depth": depth_millimetres(view.depth),
              "semantic": view.semantic, "instance": view.instance}
    written = [atomic_write(folder / names[k], png_bytes(image)) for k, image in images.items()]
    written.append(atomic_write(folder / names["camera"], _json(document)))
    return written, names


def _map_files(folder: Path, maps: FloorMaps) -> tuple[list[Path], dict[str, Any]]:
    stem = f"floor{maps.floor}"
    names = {"room_types": f"{stem}.room_types.png", "instances": f"{stem}.instances.png",
             "semantic": f"{stem}.semantic.png", "yaml": f"{stem}.maps.yaml"}
    grid = maps.grid
    yaml = (f"# cga top-down maps of floor {maps.floor}, on the grid of its ROS map "
            f"(<name>.floor{maps.floor}.yaml): same resolution and origin\n"
            f"room_types: {names['room_types']}\n"
            f"instances: {names['instances']}\n"
            f"semantic: {names['semantic']}\n"
            f"resolution: {numbers_text([grid.resolution])}\n"
            f"origin: [{numbers_text(grid.origin).replace(' ', ', ')}, 0.0]\n")
    written = [atomic_write(folder / names["room_types"], png_bytes(maps.room_type)),
               atomic_write(folder / names["instances"], png_bytes(maps.instance)),
               atomic_write(folder / names["semantic"], png_bytes(maps.semantic)),
               atomic_write(folder / names["yaml"], yaml)]
    return written, {"floor": maps.floor, "files": names, "resolution": grid.resolution,
                     "origin": list(grid.origin), "shape": list(grid.shape)}


def write_render(inputs: RenderInputs, options: RenderOptions, out_dir: Path,
                 name: str) -> list[Path]:
    """Render every view of a build and write ``<out_dir>/<name>.render/``.

    Returns
    -------
    list of Path
        The files written, ``index.json`` last.
    """
    folder = Path(out_dir) / render_folder(name)
    written: list[Path] = []
    views: list[dict[str, Any]] = []
    floors: list[dict[str, Any]] = []
    for floor in render_build(inputs, options):
        for view in floor.views:
            files, names = _view_files(folder, view)
            written += files
            views.append({"name": view.camera.name, "floor": view.camera.floor,
                          "room": view.camera.room,
                          "projection": "orthographic" if view.camera.orthographic
                          else "perspective", "files": names})
        files, entry = _map_files(folder, floor.maps)
        written += files
        floors.append({**entry, "rooms_without_view": floor.rooms_without_view})
    index = {
        "format": FORMAT,
        "name": name,
        "seed": inputs.seed,
        "options": asdict(options),
        "views": views,
        "floors": floors,
        "classes": [asdict(c) for c in class_table()],
        "instances": [{"id": s.instance_id, "path": s.path, "class_id": s.class_id}
                      for s in inputs.surfaces],
    }
    written.append(atomic_write(folder / "index.json", _json(index)))
    return written

