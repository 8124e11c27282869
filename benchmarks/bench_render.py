"""Benchmark: one 640×480 camera view (RGB + depth + semantic + instance) on one core.

Target: at most 0.2 s of CPU per view on one core (issue 16), counting every pass of
:meth:`cga.render.views.ViewRenderer.render`: pixel rays, the Embree ray cast with the
exact depth, the labels and the shading. PNG encoding of the four images is reported
beside it. Builds the grammar (default ``demos/house.grammar``) once, untimed, places the
room cameras with the default options, renders each view ``--repeats`` times and reports
the minimum and the median CPU time per pass (``time.thread_time``: this thread's CPU,
so other programs on the machine do not count) and views per second per core.
Embree is told to use one thread.

    python benchmarks/bench_render.py [--repeats 5] [--grammar demos/house.grammar]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")  # noqa: E402 - before numpy and Embree load

from cga.pipeline import build
from cga.render.files import depth_millimetres, png_bytes
from cga.render.inputs import inputs_from_scene
from cga.render.placement import (RenderOptions, floor_grid, reachable_cells, room_cameras)
from cga.render.views import ViewRenderer

TARGET_S = 0.2
DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"
PASSES = ("rays", "cast", "labels", "shade")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    scene = build(args.grammar, seed=args.seed, formats=(), physics=False, quiet=True)
    inputs = inputs_from_scene(scene, scene.nodes)
    options = RenderOptions()
    cameras = []
    for floor in inputs.floors:
        grid = floor_grid(floor, inputs, options)
        cameras += room_cameras(floor, grid, reachable_cells(grid, options.robot_radius),
                                inputs.seed, options)[0]
    renderer = ViewRenderer(inputs.surfaces)
    passes: dict[str, list[float]] = {name: [] for name in (*PASSES, "view", "png")}
    clock = time.thread_time
    for camera in cameras:
        for _ in range(args.repeats):
            started = clock()
            view = renderer.render(camera)
            passes["view"].append(clock() - started)
            started = clock()
            for image in (view.rgb, depth_millimetres(view.depth), view.semantic, view.instance):
                png_bytes(image)
            passes["png"].append(clock() - started)
            for name in PASSES:
                passes[name].append(view.seconds[name])  # CPU of each pass
    print(f"{len(cameras)} views of {args.grammar.name} (seed {args.seed}), "
          f"{len(renderer.rays)} triangles, {options.width}x{options.height}, "
          f"{args.repeats} repeats each")
    print("| pass (CPU) | min (ms) | median (ms) |")
    print("|---|---:|---:|")
    for name, values in passes.items():
        print(f"| {name} | {1000 * min(values):.1f} | "
              f"{1000 * statistics.median(values):.1f} |")
    median = statistics.median(passes["view"])
    print(f"views per second per core: {1 / median:.1f} "
          f"(with PNG encoding {1 / (median + statistics.median(passes['png'])):.1f})")
    print(f"target <= {TARGET_S} s per view: {'met' if median <= TARGET_S else 'NOT met'}")


if __name__ == "__main__":
    main()
