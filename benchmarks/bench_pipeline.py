"""Pipeline benchmarks: per-stage timings of every demo, the layout of a 10-room floor and
the furnished two-storey house end to end.

Three parts, each printed as Markdown tables (pasted into ``benchmarks/RESULTS.md``):

``demos``
    Every ``demos/*.grammar`` is built in this process ``--repeats`` times at seed 0 (one
    warm-up build first, not counted) with the files ``cga build`` writes; the table gives
    the minimum and median of each stage of ``Scene.timings`` (``derive`` includes the
    operations listed under it) and of the whole build, wall clock and CPU.
``layout``
    :mod:`bench_layout`: a 10-room floor (make_floor + type_rooms, re-draws included) on
    ``--layout-seeds`` seeds, ``--repeats`` sweeps, CPU time and reference loops.
    Target: p95 ≤ 10 ms.
``house``
    ``demos/house.grammar`` (two storeys, typed and furnished) built without physics on
    ``--house-seeds`` seeds, ``--repeats`` times each, writing the files of ``cga build``
    (glb, scene JSON, plans) or ``--formats``.
    Target: median < 0.5 s.

    python benchmarks/bench_pipeline.py [--repeats 5] [--parts demos,layout,house]
                                        [--layout-seeds 300] [--house-seeds 10] [--no-physics]
                                        [--formats glb,json,plan]

Timings are wall clock (``time.perf_counter``) unless marked CPU
(``time.process_time``); on a shared machine the CPU figures are the steadier ones.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import bench_layout
from bench_layout import p95
from cga.pipeline import build
from cga.export import DEFAULT_FORMATS

ROOT = Path(__file__).resolve().parents[1]
DEMOS = sorted((ROOT / "demos").glob("*.grammar"))
HOUSE = ROOT / "demos" / "house.grammar"

STAGES = ("parse", "derive", "make_floor", "type_rooms", "add_furniture", "meshing", "physics",
          "navigability", "export")
"""Rows of the per-demo table: pipeline stages and, indented under derive, its operations."""
OPERATIONS = {"make_floor", "type_rooms", "add_furniture"}

HOUSE_TARGET_S = 0.5


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
    "layout": lambda args, work: bench_layout.report(args.layout_seeds, args.repeats),
    "house": lambda args, work: bench_house(args.repeats, args.house_seeds, args.formats, work),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="repeats of every measurement")
    parser.add_argument("--parts", default=",".join(PARTS),
                        help=f"comma-separated parts to run ({', '.join(PARTS)})")
    parser.add_argument("--layout-seeds", type=int, default=300)
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
