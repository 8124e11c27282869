"""Benchmark: CPU per house of the navigability check and of the difficulty metrics.

Builds ``--houses`` seeds of the grammar once (untimed, with the checks, so the scenes
carry their meshes and grids), then times, ``--repeats`` times over all of them, the
navigability check (occupancy grids, clearances, reach) and the difficulty metrics
(local width, geodesics, exploration proxy) that read its grids. Prints the medians in
CPU milliseconds per house and in reference loops (``reference.py``).

    python benchmarks/bench_navigability.py [--houses 5] [--repeats 5] [--grammar FILE]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from per_house import build_houses, house_options, print_table, time_steps  # noqa: E402
from reference import ReferenceClock  # noqa: E402

from cga.checks import check_navigability  # noqa: E402
from cga.difficulty import measure_scene  # noqa: E402
from cga.scene import Scene  # noqa: E402


def _navigability(scenes: list[Scene]) -> None:
    for scene in scenes:
        scene.checks["navigability"] = check_navigability(scene)


def main() -> None:
    options = house_options(__doc__, repeats=5)
    scenes = build_houses(options, out_dir=tempfile.mkdtemp())
    figures = time_steps({
        "navigability": lambda: _navigability(scenes),
        "difficulty": lambda: [measure_scene(scene) for scene in scenes],
    }, repeats=options.repeats, houses=len(scenes), clock=(clock := ReferenceClock()))
    print(f"{options.grammar.name}: {options.houses} houses × {options.repeats} repeats")
    print_table(figures, clock)


if __name__ == "__main__":
    main()
