"""Benchmark: the physics check on a furnished house and the navigability check per floor.

Targets: physics under 2 s for a furnished two-storey house (~50–60 items); navigability
under 200 ms per floor. Each repeat builds the grammar (default ``demos/house.grammar``)
with another seed, untimed, then times the two checks on it. Prints the minimum and the
median, the item and floor counts, and how many checks passed.

    python benchmarks/bench_checks.py [--repeats 10] [--grammar demos/house.grammar]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from cga.pipeline import build
from cga.checks import check_floor_navigability, check_physics

PHYSICS_TARGET_S = 2.0
FLOOR_TARGET_MS = 200.0
DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    args = parser.parse_args()

    physics, floors, items, passed_physics, passed_floors = [], [], [], 0, 0
    for seed in range(args.repeats):
        scene = build(args.grammar, seed=seed, formats=(), physics=False, quiet=True)
        nodes = scene.nodes
        started = time.perf_counter()
        report = check_physics(scene, nodes)
        physics.append(time.perf_counter() - started)
        items.append(len(report.items))
        passed_physics += report.passed
        for plan in scene.floors:
            started = time.perf_counter()
            reach = check_floor_navigability(plan, nodes)
            floors.append(time.perf_counter() - started)
            passed_floors += reach.passed

    print(f"{args.grammar.name}: {args.repeats} seeds, {statistics.median(items):.0f} items "
          f"(median), {len(floors)} floors")
    print(f"physics      min {min(physics):6.3f} s   median {statistics.median(physics):6.3f} s"
          f"   target < {PHYSICS_TARGET_S:g} s   passed {passed_physics}/{args.repeats}")
    ms = [t * 1000 for t in floors]
    print(f"navigability min {min(ms):6.1f} ms  median {statistics.median(ms):6.1f} ms"
          f"  per floor, target < {FLOOR_TARGET_MS:g} ms   passed {passed_floors}/{len(floors)}")


if __name__ == "__main__":
    main()
