"""Render a cga glb with Blender (Cycles, CPU, headless) to a PNG.

The glb is imported with Blender's own glTF importer (materials, and the rooms'
``KHR_lights_punctual`` ceiling lights), the storeys above ``--floor`` and the roof are
removed so the camera looks into the rooms, a sun and a soft sky are added, and a
camera looks down from a corner at everything left. ``--furniture-only`` keeps only the
furniture on a transparent background (a check that items carry their colours). The
docs' picture (docs/images/blender-house.png) is::

    cga build demos/house.grammar --seed 3 --out /tmp/house --no-physics --materials random
    python scripts/render_blender.py /tmp/house/house.glb docs/images/blender-house.png

Run it with any Python: it starts ``blender -b`` (or ``$BLENDER``) on itself; inside
Blender it does the work. Blender 3.x or later (``apt-get install blender``).
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["blender_executable", "render", "main"]


def blender_executable() -> str | None:
    """``$BLENDER`` or ``blender`` on the PATH, or None."""
    return os.environ.get("BLENDER") or shutil.which("blender")


def _arguments(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("glb", type=Path, help="the glb to render")
    parser.add_argument("png", type=Path, help="the PNG to write")
    parser.add_argument("--floor", type=int, default=0,
                        help="the storey to look into (those above are removed; default 0)")
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=640)
    parser.add_argument("--samples", type=int, default=32, help="Cycles samples (default 32)")
    parser.add_argument("--furniture-only", action="store_true",
                        help="keep only the furniture, on a transparent background")
    return parser.parse_args(argv)


def render(glb: Path, png: Path, *, floor: int = 0, width: int = 960, height: int = 640,
           samples: int = 32, furniture_only: bool = False, timeout: float = 600) -> None:
    """Render ``glb`` into ``png`` with Blender in the background.

    Raises
    ------
    FileNotFoundError
        Blender is not installed.
    subprocess.CalledProcessError
        Blender failed (its output is in the exception).
    """
    blender = blender_executable()
    if blender is None:
        raise FileNotFoundError("Blender is not installed (apt-get install blender, or set "
                                "$BLENDER)")
    args = [str(Path(glb).resolve()), str(Path(png).resolve()), "--floor", str(floor),
            "--width", str(width), "--height", str(height), "--samples", str(samples)]
    if furniture_only:
        args.append("--furniture-only")
    subprocess.run([blender, "-b", "--factory-startup", "--python-exit-code", "1",
                    "--python", str(Path(__file__).resolve()),
                    "--", *args], check=True, capture_output=True, text=True, timeout=timeout)


def _numpy_alias_for_old_importers() -> None:
    """Blender 3.4's glTF importer (Debian 12's package) calls ``numpy.bool``, which
    NumPy 1.24 removed; give it the builtin it meant."""
    import numpy

    if "bool" not in numpy.__dict__:
        numpy.bool = bool  # type: ignore[attr-defined]


def _in_blender(options: argparse.Namespace) -> None:
    import bpy  # type: ignore[import-not-found]
    from mathutils import Vector  # type: ignore[import-not-found]

    _numpy_alias_for_old_importers()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(options.glb))

    def storey(obj: object) -> int | None:
        # objects are named by their glTF node path: floor{i}/...
        name = obj.name  # type: ignore[attr-defined]
        head = name.split("/", 1)[0]
        return int(head[5:]) if head.startswith("floor") and head[5:].isdigit() else None

    doomed = []
    for obj in bpy.data.objects:
        k = storey(obj)
        above = k is not None and k > options.floor
        roof = obj.name.endswith("/roof")
        not_furniture = obj.type == "MESH" and "/furniture/" not in obj.name
        if above or roof or (options.furniture_only and not_furniture):
            doomed.append(obj)
    for obj in doomed:
        bpy.data.objects.remove(obj, do_unlink=True)

    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    corners = [o.matrix_world @ Vector(c) for o in meshes for c in o.bound_box]
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    centre = (lo + hi) / 2
    size = max((hi - lo).length, 1.0)

    scene = bpy.context.scene
    camera_data = bpy.data.cameras.new("camera")
    camera_data.lens = 35
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    elevation, azimuth = math.radians(55), math.radians(-60)
    distance = 0.95 * size / (2 * math.tan(camera_data.angle / 2))
    direction = Vector((math.cos(elevation) * math.cos(azimuth),
                        math.cos(elevation) * math.sin(azimuth), math.sin(elevation)))
    camera.location = centre + direction * distance
    camera.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    scene.camera = camera

    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(10)
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (math.radians(35), math.radians(10), math.radians(-30))
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.8, 0.85, 0.9, 1.0)
    background.inputs["Strength"].default_value = 0.6
    scene.world = world

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = options.samples
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 4
    scene.cycles.sample_clamp_indirect = 1.0  # few samples: no fireflies
    scene.cycles.caustics_reflective = False
    scene.cycles.caustics_refractive = False
    scene.render.resolution_x = options.width
    scene.render.resolution_y = options.height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = options.furniture_only
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA" if options.furniture_only else "RGB"
    scene.render.filepath = str(options.png)
    bpy.ops.render.render(write_still=True)


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point, outside or inside Blender."""
    argv = sys.argv[1:] if argv is None else argv
    if "--" in argv:  # inside Blender: our arguments follow "--"
        argv = argv[argv.index("--") + 1:]
    options = _arguments(argv)
    try:
        import bpy  # type: ignore[import-not-found]  # noqa: F401
    except ImportError:
        render(options.glb, options.png, floor=options.floor, width=options.width,
               height=options.height, samples=options.samples,
               furniture_only=options.furniture_only)
        print(options.png)
        return 0
    _in_blender(options)
    return 0


if __name__ == "__main__":
    sys.exit(main())
