"""Benchmark: CPU time of the physics check alone, per house, and of its stages.

Builds ``--seeds`` houses once (untimed, without physics), runs one untimed check to warm
the per-model caches, then times ``check_physics`` on every house ``--repeats`` times
with CPU time (``time.process_time``). Prints the median CPU seconds per house, the same
as a multiple of the reference loop (``benchmarks/reference.py``, sampled between
repeats), and the median per house of each stage of the check: the structure's static
bodies, the items' bodies, the initial overlaps and the settling.

    python benchmarks/bench_physics.py [--seeds 5] [--repeats 3] [--grammar demos/house.grammar]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

from cga.checks import physics  # noqa: E402
from cga.pipeline import build  # noqa: E402

DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"
STAGES = ("add_static", "add_item", "penetrations", "settle")


def _timed(method: Callable[..., Any], name: str, spent: Counter[str]) -> Callable[..., Any]:
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        started = time.process_time()
        try:
            return method(*args, **kwargs)
        finally:
            spent[name] += time.process_time() - started
    return wrapper


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    args = parser.parse_args()

    scenes = [build(args.grammar, seed=seed, formats=(), physics=False, quiet=True)
              for seed in range(1, args.seeds + 1)]
    for scene in scenes:
        scene.nodes  # meshing is not part of the check
    spent: Counter[str] = Counter()
    for name in STAGES:
        setattr(physics._World, name, _timed(getattr(physics._World, name), name, spent))
    physics.check_physics(scenes[0])  # warm: per-model mass properties and shapes
    clock = ReferenceClock()
    totals, stages = [], []
    for _ in range(args.repeats):
        clock.sample()
        spent.clear()
        started = time.process_time()
        items = sum(len(physics.check_physics(scene).items) for scene in scenes)
        totals.append((time.process_time() - started) / len(scenes))
        stages.append({name: spent[name] / len(scenes) for name in STAGES})
    clock.sample()
    median = statistics.median(totals)
    print(f"{args.grammar.name}: {len(scenes)} houses, {items / len(scenes):.0f} items each; "
          f"{clock.describe()}")
    print(f"physics per house: median {median:.3f} s CPU ({clock.ratio(median):,.0f} reference "
          f"loops), min {min(totals):.3f} s")
    print("stages (median s CPU per house): " + ", ".join(
        f"{name} {statistics.median(s[name] for s in stages):.3f}" for name in STAGES))


if __name__ == "__main__":
    main()
