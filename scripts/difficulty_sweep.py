"""Measured difficulty of the UvA demo per difficulty knob value (docs/difficulty.md, "The
sweep").

``cga batch demos/usar_maze.grammar -n 50 --sweep difficulty=0:10`` gives the same table
with full builds (physics, exports); this script keeps the measurement cheap for the
issue's 11 × 50 maps: per map it derives the floor (layout and furniture), meshes it,
runs the navigability check at a coarser grid (``--resolution``, default 0.1 m) and
measures the difficulty; no physics check, no files. It prints one table of metric
means (and standard deviations) per value and writes every map's metrics as JSON lines.

Usage::

    python scripts/difficulty_sweep.py --seeds 50 --out sweep.jsonl
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from cga.checks.navigability import check_navigability
from cga.difficulty import METRICS, measure_scene
from cga.pipeline import build

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grammar", default=str(ROOT / "demos" / "usar_maze.grammar"))
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--values", default="0:10", help="LO:HI of the difficulty")
    parser.add_argument("--resolution", type=float, default=0.1)
    parser.add_argument("--out", default="difficulty_sweep.jsonl")
    args = parser.parse_args(argv)
    lo, hi = (int(v) for v in args.values.split(":"))
    rows: dict[int, list[dict]] = {}
    with open(args.out, "w", encoding="utf-8") as out:
        for d in range(lo, hi + 1):
            for seed in range(args.seeds):
                scene = build(args.grammar, seed=seed, formats=(), physics=False, quiet=True,
                              overrides={"difficulty": str(d)})
                scene.checks["navigability"] = check_navigability(scene,
                                                                  resolution=args.resolution)
                report = measure_scene(scene)
                assert report is not None
                row = {"difficulty": d, "seed": seed,
                       "navigable": scene.checks["navigability"].passed, **report.totals()}
                rows.setdefault(d, []).append(row)
                out.write(json.dumps(row) + "\n")
                out.flush()
            print(f"difficulty {d}: {len(rows[d])} maps", file=sys.stderr, flush=True)
    print("| d | " + " | ".join(METRICS) + " |")
    print("|---" * (len(METRICS) + 1) + "|")
    for d, maps in rows.items():
        cells = []
        for name in METRICS:
            values = [m[name] for m in maps if m[name] is not None]
            mean = sum(values) / len(values)
            sd = math.sqrt(sum((v - mean) ** 2 for v in values) / max(1, len(values) - 1))
            cells.append(f"{mean:.3g} ± {sd:.2g}")
        print(f"| {d} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
