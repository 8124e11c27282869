"""Furniture at full disorder keeps every guarantee: the issue's 300-floor measurement.

Furnishes random house and office floors (the tiling of
``tests/property/test_furniture_props.py``: a hall along the middle, rooms across both
sides, typed by the shipped tables) with the shipped furniture tables at disorder 0, 0.4
and 1, runs the independent validator (``tests/support/furniture_checks.py``) on every
floor at disorder 1 and prints how many floors break a guarantee, the mean free turn of
the chairs per disorder and the CPU time. The test suite runs a short version
(``tests/property/test_variation_props.py``).

Usage::

    python scripts/disorder_check.py --floors 300
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from cga.authoring import furnish_floor  # noqa: E402
from cga.operations.furniture.disorder import MAX_YAW  # noqa: E402
from cga.operations.furniture.library import default_library  # noqa: E402
from furniture_checks import furniture_violations  # noqa: E402
from hall_floors import typed_hall_floor  # noqa: E402

LEVELS = (0.0, 0.4, 1.0)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--floors", type=int, default=300, help="floors to furnish")
    args = parser.parse_args(argv)
    library = default_library()
    yaws: dict[float, list[float]] = {level: [] for level in LEVELS}
    broken, floors, seed = [], 0, 0
    start = time.process_time()
    while floors < args.floors:
        seed += 1
        kind = "office" if seed % 2 == 0 else "house"
        floor = typed_hall_floor(kind, seed)
        if floor is None:
            continue
        typed, table = floor
        floors += 1
        for level in LEVELS:
            furnished = furnish_floor(typed, table, seed=seed, clearance_tries=5,
                                      disorder=level, library=library)
            yaws[level] += [abs(i.yaw) for i in furnished.furniture if i.model.endswith("chair")]
            if level == 1.0:
                problems = furniture_violations(furnished, ROOT / "rules" / table,
                                                max_yaw=MAX_YAW)
                if problems:
                    broken.append((seed, kind, problems[:3]))
    seconds = time.process_time() - start
    print(f"{floors} floors (seeds 1..{seed}), {len(broken)} break a guarantee at disorder 1")
    for seed, kind, problems in broken:
        print(f"  seed {seed} ({kind}): {problems}")
    for level, values in yaws.items():
        moved = sum(1 for v in values if v > 0)
        print(f"disorder {level:g}: {len(values)} chairs, {moved} turned, mean |yaw| "
              f"{math.degrees(float(np.mean(values))) if values else 0.0:.2f}°")
    print(f"CPU {seconds:.1f} s ({seconds / floors / len(LEVELS) * 1000:.0f} ms per furnished floor)")
    return 1 if broken else 0


if __name__ == "__main__":
    raise SystemExit(main())
