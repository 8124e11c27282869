"""What the per-house stage benchmarks share (``bench_meshing.py``, ``bench_exports.py``,
``bench_navigability.py``): their command line, the houses built once and untimed, the
steps timed round after round with the reference loop sampled between rounds
(``reference.py``), and the table of CPU milliseconds per house they print."""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from reference import ReferenceClock

from cga.pipeline import build
from cga.scene import Scene

__all__ = ["DEFAULT_GRAMMAR", "house_options", "build_houses", "time_steps", "print_table"]

DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"


def house_options(doc: str, *, repeats: int = 7) -> argparse.Namespace:
    """``--repeats`` (rounds), ``--houses`` (seeds 1..N) and ``--grammar``, parsed."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=repeats)
    parser.add_argument("--houses", type=int, default=5)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    return parser.parse_args()


def build_houses(options: argparse.Namespace, **build_options: Any) -> list[Scene]:
    """Seeds 1..``--houses`` of ``--grammar``, built once (no files unless asked)."""
    build_options = {"formats": (), "quiet": True, **build_options}
    return [build(options.grammar, seed=seed, **build_options)
            for seed in range(1, options.houses + 1)]


def time_steps(steps: Mapping[str, Callable[[], object]], *, repeats: int, houses: int,
               clock: ReferenceClock) -> dict[str, list[float]]:
    """CPU seconds per house of each step (each call covers all ``houses``), one value
    per round; the reference loop is sampled before each round."""
    figures: dict[str, list[float]] = {name: [] for name in steps}
    for _ in range(repeats):
        clock.sample()
        for name, step in steps.items():
            started = time.process_time()
            step()
            figures[name].append((time.process_time() - started) / houses)
    return figures


def print_table(figures: Mapping[str, list[float]], clock: ReferenceClock) -> None:
    """Minimum and median milliseconds per house, and the median in reference loops."""
    print("| step | min ms/house | median ms/house | median / ref |")
    print("|---|---|---|---|")
    for name, values in figures.items():
        median = statistics.median(values)
        print(f"| {name} | {min(values) * 1e3:.1f} | {median * 1e3:.1f} | "
              f"{clock.ratio(median):.1f} |")
    print(clock.describe())
