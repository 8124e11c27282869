"""Time make_floor and the meshing of its plan on a 14 m × 10 m storey with 10 rooms.

Targets: make_floor (BSP, DCEL, rooms, walls, windows) under 5 ms; meshing (wall
solids with openings cut by manifold3d, slab, ceiling) under 20 ms. Prints the minimum
and the median wall-clock time over repeats, each repeat on another seed, and the median
CPU time of the process (closer to the unloaded figure on a busy machine).

    python benchmarks/bench_make_floor.py [--repeats 50]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from shapely.geometry import box

from cga.model import Opening
from cga.operation import OperationContext
from cga.meshing.solids import floor_nodes
from cga.operations.make_floor import MakeFloor
from cga.shape import Mass, Shape

ARGS = {p.name: p.default for p in MakeFloor.params if not p.required} | {"split": 9, "wallWidth": 0.2, "windows": (2, 1.2, 1.2), "doorWidth": 0.9,
        "doorHeight": 2.1, "min_room_width": 2.4, "min_room_area": 6.0,
        "cut_range": (0.35, 0.65), "same_layout": False, "window_sill": 0.9}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=50)
    repeats = parser.parse_args().repeats

    mass = Mass(box(0, 0, 14, 10), 0.0, 3.0)
    shape = Shape("Floor", ("Lot", "Floor"), mass.scope(), mass, {"floor": 0})
    operation = MakeFloor()
    partition_times, mesh_times, rooms, walls = [], [], [], []
    for seed in range(repeats):
        ctx = OperationContext(rng=np.random.default_rng(seed), units=1.0,
                               resolve=lambda path, kind="rules": path, report=lambda d: None,
                               span=None, successor_count=1, seed=seed)
        [child], seconds = _timed(operation.apply, shape, ARGS, ctx)
        partition_times.append(seconds)
        plan = _with_doors(child.plan).with_changes(is_top=True)
        nodes, seconds = _timed(floor_nodes, plan)
        mesh_times.append(seconds)
        rooms.append(len(plan.rooms))
        walls.append(sum(1 for n in nodes if n.kind == "wall"))

    print(f"14 x 10 m storey, split 9: {statistics.mean(rooms):.1f} rooms, "
          f"{statistics.mean(walls):.1f} wall solids on average, {repeats} seeds")
    _report("make_floor (BSP + DCEL + plan)", partition_times, 5.0)
    _report("meshing (walls with doors and windows, slabs)", mesh_times, 20.0)


def _timed(function, *args):
    """The result and (wall-clock, CPU) seconds of one call."""
    wall, cpu = time.perf_counter(), time.process_time()
    result = function(*args)
    return result, (time.perf_counter() - wall, time.process_time() - cpu)


def _with_doors(plan):
    """One door in the middle of every inner wall long enough, as type_rooms would add."""
    walls = tuple(w.with_opening(Opening("door", w.length / 2, 0.9, 2.1))
                  if not w.outer and w.length >= 1.5 else w for w in plan.walls)
    return plan.with_changes(walls=walls)


def _report(what: str, seconds: list[tuple[float, float]], target_ms: float) -> None:
    wall = [w * 1000 for w, _ in seconds]
    cpu = statistics.median(c for _, c in seconds) * 1000
    median = statistics.median(wall)
    verdict = "ok" if min(median, cpu) < target_ms else "over target"
    print(f"{what:46s} min {min(wall):6.2f} ms  median {median:6.2f} ms  "
          f"(cpu median {cpu:6.2f} ms)  target {target_ms:g} ms: {verdict}")


if __name__ == "__main__":
    main()
