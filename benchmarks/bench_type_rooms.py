"""Benchmark: type_rooms (typing + room graph + doors) on 12-room floors; target < 5 ms.

Run ``python benchmarks/bench_type_rooms.py [--repeat N]``. Three 12-room floors (a
4×3 grid and a row-and-wing house typed with the thesis' table, a strip of offices on
both sides of a corridor typed with the shipped office table and its access rules) are
typed; each case is timed ``repeat`` times with a fresh seed per run and the minimum and
median are printed. The rule table is parsed once, outside the timing, as
the operation does (it caches tables per build); the floor is built once per case.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.roomtyping.rules import load_rule_table
from cga.operations.type_rooms import type_plan
from cga.resources import resolve_resource

TARGET_MS = 5.0

FLOORS = {
    "grid 4x3": [(x, z, x + 4.0, z + 3.5) for x in (0.0, 4.0, 8.0, 12.0) for z in (0.0, 3.5, 7.0)],
    "house": [(0, 0, 7, 5), (7, 0, 11, 5), (11, 0, 14, 5), (14, 0, 18, 5), (0, 5, 4, 10),
              (4, 5, 9, 10), (9, 5, 12, 10), (12, 5, 18, 10), (0, 10, 5, 14), (5, 10, 10, 14),
              (10, 10, 14, 14), (14, 10, 18, 14)],
    "offices": [(0, 0, 1.8, 5), (1.8, 0, 3.6, 5), (3.6, 0, 8, 5), (8, 0, 12, 5), (12, 0, 18, 5),
                (18, 0, 24, 5)]  # toilets of 9 m², offices, meeting rooms
               + [(4.0 * i, 6.8, 4.0 * i + 4.0, 11.8) for i in range(6)]
               + [(0, 5, 24, 6.8)],  # the corridor, room 12
}
TABLES = {"grid 4x3": "thesis_types.csv", "house": "thesis_types.csv",
          "offices": "office_types.csv"}
CIRCULATION = {"offices": (12,)}


def bench(repeat: int) -> list[tuple[str, float, float]]:
    """(case, min ms, median ms) for every floor."""
    results = []
    for name, rectangles in FLOORS.items():
        plan = plan_from_rectangles(rectangles, circulation=CIRCULATION.get(name, ()))
        table = load_rule_table(resolve_resource(TABLES[name], "rules"))
        assert len(plan.rooms) - len(CIRCULATION.get(name, ())) == 12
        times = []
        for seed in range(repeat):
            rng = np.random.default_rng(seed)
            start = time.perf_counter()
            type_plan(plan, table, rng)
            times.append((time.perf_counter() - start) * 1e3)
        results.append((name, min(times), statistics.median(times)))
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=200)
    options = parser.parse_args()
    print(f"type_rooms, 12 rooms, {options.repeat} seeds each (target < {TARGET_MS} ms)")
    for name, fastest, median in bench(options.repeat):
        verdict = "ok" if median < TARGET_MS else "SLOW"
        print(f"  {name:10s} min {fastest:6.2f} ms   median {median:6.2f} ms   {verdict}")


if __name__ == "__main__":
    main()
