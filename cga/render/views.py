"""Render a view: one ray cast, then RGB, depth, semantic and instance images.

:meth:`ViewRenderer.render` is the per-view kernel; :func:`render_build` plans every view of a
build (the room cameras and a top-down view per floor, :mod:`.placement`) and renders
them, with the floor's top-down maps on the ROS map's grid.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from cga.checks.occupancy import OccupancyGrid
from cga.semantics import room_type_class

from .cameras import Camera
from .inputs import FloorOutline, RenderInputs
from .placement import (RenderOptions, floor_grid, reachable_cells, room_cameras, room_map,
                        top_camera)
from .raycast import RayScene, Surface
from .shading import Shader

__all__ = ["ViewImages", "FloorMaps", "ViewRenderer", "render_build"]


@dataclass(frozen=True)
class ViewImages:
    """The images of one view, each ``[height, width]`` (RGB ``[height, width, 3]``).

    ``depth`` is metres along the optical axis (``inf`` where the ray hit nothing);
    ``semantic`` holds class ids, ``instance`` instance ids (0: nothing).
    ``seconds`` splits the CPU time of the rendering thread: ``rays`` (pixel rays),
    ``cast`` (Embree and the exact depth), ``labels``, ``shade``.
    """

    camera: Camera
    rgb: np.ndarray
    depth: np.ndarray
    semantic: np.ndarray
    instance: np.ndarray
    seconds: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class FloorMaps:
    """A floor's top-down maps on its ROS map's grid (same shape, origin, resolution):
    ``room_type`` (room-type class of the room holding each cell centre) and
    ``instance`` (the instance seen from above at each cell centre)."""

    floor: int
    grid: OccupancyGrid
    room_type: np.ndarray
    instance: np.ndarray
    semantic: np.ndarray


class ViewRenderer:
    """Renders views of some surfaces: their ray scene and shader, made once."""

    def __init__(self, surfaces: Sequence[Surface]):
        self.rays = RayScene(surfaces)
        self.shader = Shader(self.rays)

    def render(self, camera: Camera) -> ViewImages:
        """All images of one view from one ray cast per pixel."""
        clock = time.thread_time  # CPU of this thread: other programs do not count
        start = clock()
        origins, directions = camera.rays()
        after_rays = clock()
        hits = self.rays.cast(origins, directions, common_origin=len(origins) == 1)
        after_cast = clock()
        semantic, instance = self.rays.labels(hits)
        depth = hits.t.astype(np.float32)
        after_labels = clock()
        rgb = self.shader(hits, directions)
        done = clock()
        shape = (camera.height, camera.width)
        return ViewImages(camera, rgb.reshape(*shape, 3), depth.reshape(shape),
                          semantic.reshape(shape), instance.reshape(shape),
                          {"rays": after_rays - start, "cast": after_cast - after_rays,
                           "labels": after_labels - after_cast, "shade": done - after_labels})


@dataclass(frozen=True)
class FloorRender:
    """What :func:`render_build` makes for one floor: its views (room views first, the
    top-down view last), its maps and the rooms that got no camera."""

    floor: int
    views: list[ViewImages]
    maps: FloorMaps
    rooms_without_view: list[int]


def render_build(inputs: RenderInputs, options: RenderOptions) -> Iterator[FloorRender]:
    """Render every floor of a build (module notes), one floor at a time."""
    if not inputs.floors:
        return
    whole = ViewRenderer(inputs.surfaces)  # room views see the storeys above and below
    for floor in inputs.floors:
        grid = floor_grid(floor, inputs, options)
        cameras, without = room_cameras(floor, grid, reachable_cells(grid, options.robot_radius),
                                        inputs.seed, options)
        views = [whole.render(camera) for camera in cameras]
        above = ViewRenderer(inputs.floor_surfaces(floor.index))
        views.append(above.render(top_camera(floor, grid, options.top_oversample,
                                             f"floor{floor.index}_top")))
        yield FloorRender(floor.index, views, _maps(floor, grid, above), without)


def _maps(floor: FloorOutline, grid: OccupancyGrid, above: ViewRenderer) -> FloorMaps:
    cells = above.render(top_camera(floor, grid, 1, f"floor{floor.index}_map"))
    types = room_map(floor, grid, [room_type_class(r.type) for r in floor.rooms])
    return FloorMaps(floor.index, grid, types, cells.instance, cells.semantic)
