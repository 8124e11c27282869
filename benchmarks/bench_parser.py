"""Time parsing every demo grammar (the parser is built once per process, then reused).

Target: a 30-line grammar parses in under 25 ms. Prints, per demo, its lines and the
minimum and median wall-clock time and the median CPU time over repeats (a test used to
assert the time and failed whenever the machine was busy; the figure belongs here).

    python benchmarks/bench_parser.py [--repeats 20]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from cga.parser import parse

DEMOS = Path(__file__).resolve().parents[1] / "demos"
TARGET_MS = 25.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=20)
    repeats = parser.parse_args().repeats
    grammars = sorted(DEMOS.glob("*.grammar"))
    parse(grammars[0].read_text(encoding="utf-8"))  # builds the parser: not timed
    print("| grammar | lines | min ms | median ms | median CPU ms |")
    print("|---|---:|---:|---:|---:|")
    worst = 0.0
    for path in grammars:
        text = path.read_text(encoding="utf-8")
        walls, cpus = [], []
        for _ in range(repeats):
            wall, cpu = time.perf_counter(), time.process_time()
            parse(text, str(path))
            walls.append((time.perf_counter() - wall) * 1000)
            cpus.append((time.process_time() - cpu) * 1000)
        worst = max(worst, statistics.median(cpus))
        print(f"| {path.name} | {len(text.splitlines())} | {min(walls):.2f} | "
              f"{statistics.median(walls):.2f} | {statistics.median(cpus):.2f} |")
    verdict = "met" if worst < TARGET_MS else "NOT met"
    print(f"\nTarget: every demo parses in under {TARGET_MS:g} ms of CPU (median of {repeats}; "
          f"wall-clock time on a busy machine is longer): {verdict}")


if __name__ == "__main__":
    main()
