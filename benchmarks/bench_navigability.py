"""Benchmark: CPU per house of the navigability check and of the difficulty metrics.

Builds ``--houses`` seeds of the grammar once (untimed, with the checks, so the scenes
carry their meshes and grids), then times, ``--repeats`` times over all of them, the
navigability check (occupancy grids, clearances, reach) and the difficulty metrics
(local width, geodesics, exploration proxy) that read its grids. Prints the medians in
CPU seconds per house and in reference loops (``reference.py``).

    python benchmarks/bench_navigability.py [--houses 5] [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from cga.checks import check_navigability
from cga.difficulty import measure_scene
from cga.pipeline import build

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    parser.add_argument("--houses", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    out = tempfile.mkdtemp()
    scenes = [build(args.grammar, seed=seed, out_dir=out, formats=(), quiet=True)
              for seed in range(1, args.houses + 1)]
    clock = ReferenceClock()
    stages: dict[str, list[float]] = {"navigability": [], "difficulty": []}
    for _ in range(args.repeats):
        started = time.process_time()
        for scene in scenes:
            scene.checks["navigability"] = check_navigability(scene)
        stages["navigability"].append((time.process_time() - started) / len(scenes))
        clock.sample()
        started = time.process_time()
        for scene in scenes:
            measure_scene(scene)
        stages["difficulty"].append((time.process_time() - started) / len(scenes))
        clock.sample()
    print(f"{args.grammar.name}: {args.houses} houses × {args.repeats} repeats")
    for name, values in stages.items():
        median = statistics.median(values)
        print(f"{name:13s} CPU per house median {median:.4f} s "
              f"({clock.ratio(median):,.1f} × ref), min {min(values):.4f} s")
    print(clock.describe())


if __name__ == "__main__":
    main()
