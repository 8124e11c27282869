"""Pipeline benchmarks: per-stage timings of every demo, the layout of a 10-room floor and
the furnished two-storey house end to end.

Three parts, each printed as Markdown tables (pasted into ``benchmarks/RESULTS.md``):

``demos``
    Every ``demos/*.grammar`` is built in this process ``--repeats`` times at seed 0 (one
    warm-up build first, not counted) with the files ``cga build`` writes; the table gives
    the minimum and median of each stage of ``Scene.timings`` (``derive`` includes the
    operations listed under it) and of the whole build, wall clock and CPU.
``layout``
    A 14 m x 10 m storey cut into 10 rooms (``make_floor`` with split 9), typed with the
    shipped ``house_types.csv`` (``type_rooms``: typing, room graph, doors), on
    ``--layout-seeds`` seeds. The p95 over the seeds is computed per sweep; the sweep is
    repeated ``--repeats`` times and the minimum and median p95 are reported, wall clock
    and CPU (a few milliseconds are at the mercy of the scheduler on a busy machine).
    Target: p95 < 10 ms.
``house``
    ``demos/house.grammar`` (two storeys, typed and furnished) built without physics on
    ``--house-seeds`` seeds, ``--repeats`` times each, writing the files of ``cga build``
    (glb, scene JSON, plans) or ``--formats``.
    Target: median < 0.5 s.

    python benchmarks/bench_pipeline.py [--repeats 5] [--parts demos,layout,house]
                                        [--layout-seeds 500] [--house-seeds 10] [--no-physics]
                                        [--formats glb,json,plan]

Timings are wall clock (``time.perf_counter``) unless marked CPU
(``time.process_time``); on a shared machine the CPU figures are the steadier ones.
"""

from __future__ import annotations

import argparse
import math
import statistics
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from shapely.geometry import box

from cga.pipeline import build
from cga.errors import NoSolutionError
from cga.export import DEFAULT_FORMATS
from cga.operation import OperationContext
from cga.operations.make_floor import MakeFloor
from cga.operations.roomtyping.rules import RuleTable, load_rule_table
from cga.operations.type_rooms import type_plan
from cga.resources import resolve_resource
from cga.shape import Mass, Shape

ROOT = Path(__file__).resolve().parents[1]
DEMOS = sorted((ROOT / "demos").glob("*.grammar"))
HOUSE = ROOT / "demos" / "house.grammar"

STAGES = ("parse", "derive", "make_floor", "type_rooms", "add_furniture", "meshing", "physics",
          "navigability", "export")
"""Rows of the per-demo table: pipeline stages and, indented under derive, its operations."""
OPERATIONS = {"make_floor", "type_rooms", "add_furniture"}

LAYOUT_TARGET_MS = 10.0
HOUSE_TARGET_S = 0.5

FLOOR_ARGS = {p.name: p.default for p in MakeFloor.params if not p.required} | {
    "split": 9, "wallWidth": 0.2, "windows": (2, 1.2, 1.2), "doorWidth": 0.9,
    "doorHeight": 2.1, "min_room_width": 2.0, "min_room_area": 4.0,
    "corridor": "spine", "corridor_width": 1.6, "corridor_position": 0.42}
"""make_floor arguments of the layout benchmark (the house demo's hall and sizes, 10 rooms
besides the hall)."""


def p95(values: Sequence[float]) -> float:
    """The nearest-rank 95th percentile."""
    ordered = sorted(values)
    return ordered[max(0, math.ceil(0.95 * len(ordered)) - 1)]


def _ms(seconds: float) -> str:
    return f"{seconds * 1000:.1f}"


def _verdict(value: float, target: float) -> str:
    return "met" if value < target else "NOT met"


def _timed_build(grammar: Path, seed: int, out_dir: Path, physics: bool,
                 formats: Sequence[str] = DEFAULT_FORMATS) -> tuple[dict[str, float], float, float]:
    """(scene timings, wall seconds, CPU seconds) of one build writing ``formats``."""
    wall, cpu = time.perf_counter(), time.process_time()
    scene = build(grammar, seed=seed, out_dir=out_dir, formats=formats, physics=physics,
                  quiet=True)
    return dict(scene.timings), time.perf_counter() - wall, time.process_time() - cpu


def bench_demos(repeats: int, physics: bool, work: Path) -> None:
    print(f"## Per-stage timings of the demos (seed 0, {repeats} repeats after a warm-up, "
          f"physics {'on' if physics else 'off'}; ms)\n")
    for grammar in DEMOS:
        out = work / grammar.stem
        _timed_build(grammar, 0, out, physics)
        runs = [_timed_build(grammar, 0, out, physics) for _ in range(repeats)]
        print(f"### {grammar.name}\n")
        print("| stage | min | median |")
        print("|---|---:|---:|")
        for stage in STAGES:
            values = [timings.get(stage) for timings, _, _ in runs]
            if any(v is None for v in values):
                continue
            label = f"&nbsp;&nbsp;{stage}" if stage in OPERATIONS else stage
            print(f"| {label} | {_ms(min(values))} | {_ms(statistics.median(values))} |")
        for label, index in (("**total (wall)**", 1), ("**total (CPU)**", 2)):
            values = [run[index] for run in runs]
            print(f"| {label} | {_ms(min(values))} | {_ms(statistics.median(values))} |")
        print()


def _layout_once(seed: int, shape: Shape, table: RuleTable) -> tuple[float, float, bool]:
    """(wall, CPU) seconds of make_floor + type_rooms on one seed, and whether typing
    found a solution."""
    rng = np.random.default_rng(seed)
    ctx = OperationContext(rng=rng, units=1.0, resolve=lambda path, kind="rules": path,
                           report=lambda diagnostic: None, span=None, successor_count=1,
                           seed=seed)
    wall, cpu = time.perf_counter(), time.process_time()
    [child] = MakeFloor().apply(shape, FLOOR_ARGS, ctx)
    try:
        type_plan(child.plan, table, rng)
        typed = True
    except NoSolutionError:
        typed = False
    return time.perf_counter() - wall, time.process_time() - cpu, typed


def bench_layout(repeats: int, seeds: int) -> None:
    mass = Mass(box(0, 0, 14, 10), 0.0, 3.0)
    shape = Shape("Floor", ("Lot", "Floor"), mass.scope(), mass, {"floor": 0})
    table = load_rule_table(resolve_resource("house_types.csv", "rules"))
    _layout_once(0, shape, table)
    sweeps: dict[str, list[list[float]]] = {"wall": [], "CPU": []}
    failed = 0
    for _ in range(repeats):
        runs = [_layout_once(seed, shape, table) for seed in range(seeds)]
        sweeps["wall"].append([run[0] for run in runs])
        sweeps["CPU"].append([run[1] for run in runs])
        failed += sum(not run[2] for run in runs)
    print(f"## Layout of a 10-room floor (14 m x 10 m, a hall and make_floor split 9 + "
          f"type_rooms with house_types.csv: typing, doors, re-draws included; {seeds} seeds "
          f"x {repeats} sweeps; ms)\n")
    print("| clock | min | median | p95 (best sweep) | p95 (median sweep) | max |")
    print("|---|---:|---:|---:|---:|---:|")
    for clock, per_sweep in sweeps.items():
        every = [t for sweep in per_sweep for t in sweep]
        p95s = [p95(sweep) for sweep in per_sweep]
        print(f"| {clock} | {_ms(min(every))} | {_ms(statistics.median(every))} | "
              f"{_ms(min(p95s))} | {_ms(statistics.median(p95s))} | {_ms(max(every))} |")
    median_p95 = statistics.median(p95(sweep) for sweep in sweeps["wall"])
    print(f"\nTyping without a solution: {failed / repeats:g} of {seeds} seeds (timed too). "
          f"Target p95 < {LAYOUT_TARGET_MS:g} ms: {_verdict(median_p95, LAYOUT_TARGET_MS / 1000)} "
          f"({_ms(median_p95)} ms wall, median sweep)\n")


def bench_house(repeats: int, seeds: int, formats: Sequence[str], work: Path) -> None:
    _timed_build(HOUSE, 0, work / "house-warmup", False, formats)
    walls: list[float] = []
    cpus: list[float] = []
    stages: dict[str, list[float]] = {}
    for _ in range(repeats):
        for seed in range(seeds):
            timings, wall, cpu = _timed_build(HOUSE, seed, work / "house", False, formats)
            walls.append(wall)
            cpus.append(cpu)
            for stage, seconds in timings.items():
                stages.setdefault(stage, []).append(seconds)
    print(f"## Furnished two-storey house end to end, no physics ({seeds} seeds x {repeats} "
          f"repeats, files: {', '.join(formats)}; ms)\n")
    print("| figure | min | median | p95 |")
    print("|---|---:|---:|---:|")
    for label, values in (("total (wall)", walls), ("total (CPU)", cpus),
                          *((stage, stages[stage]) for stage in STAGES if stage in stages)):
        print(f"| {label} | {_ms(min(values))} | {_ms(statistics.median(values))} | "
              f"{_ms(p95(values))} |")
    median = statistics.median(walls)
    print(f"\nTarget < {HOUSE_TARGET_S:g} s: {_verdict(median, HOUSE_TARGET_S)} "
          f"({median:.3f} s median wall, {statistics.median(cpus):.3f} s median CPU)\n")


def _format_list(text: str) -> list[str]:
    return [f.strip() for f in text.split(",") if f.strip()]


PARTS: dict[str, Callable[[argparse.Namespace, Path], None]] = {
    "demos": lambda args, work: bench_demos(args.repeats, not args.no_physics, work),
    "layout": lambda args, work: bench_layout(args.repeats, args.layout_seeds),
    "house": lambda args, work: bench_house(args.repeats, args.house_seeds, args.formats, work),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="repeats of every measurement")
    parser.add_argument("--parts", default=",".join(PARTS),
                        help=f"comma-separated parts to run ({', '.join(PARTS)})")
    parser.add_argument("--layout-seeds", type=int, default=500)
    parser.add_argument("--house-seeds", type=int, default=10)
    parser.add_argument("--formats", type=_format_list, default=list(DEFAULT_FORMATS),
                        help="files the house part writes, comma-separated "
                             f"(default: {','.join(DEFAULT_FORMATS)}, as cga build)")
    parser.add_argument("--no-physics", action="store_true",
                        help="build the demos without the physics and navigability checks")
    args = parser.parse_args()
    parts = [p.strip() for p in args.parts.split(",") if p.strip()]
    unknown = [p for p in parts if p not in PARTS]
    if unknown or args.repeats < 1:
        parser.error(f"unknown parts {unknown}" if unknown else "--repeats must be ≥ 1")
    with tempfile.TemporaryDirectory(prefix="cga-bench-") as work:
        for part in parts:
            PARTS[part](args, Path(work))


if __name__ == "__main__":
    main()
