"""add_furniture on one crowded room: how the cost grows with the items per room.

A 16 m × 16 m living room with one door and a window per wall is furnished with
``n`` items (every fourth a bookshelf along a wall, the others free-standing chairs;
5 cm side and front clearances) for n = 16, 32, 64 and 128, one attempt per seed (the
solver's own restarts are a separate factor). The table gives the median CPU time over
``--repeat`` seeds, the same as a multiple of the reference loop (``reference.py``,
timed in this run), how many items were placed, and the growth exponent between
successive sizes (1: linear, 2: quadratic).

    python benchmarks/bench_crowded_room.py [--repeat 3] [--sizes 16,32,64,128]
                                            [--passage-width 0.6]

``--passage-width 0`` switches the passage rule off, to time the placement alone: in a
room this full most poses tried would wall off part of the floor, and telling by how
much takes the pieces of the floor each pose leaves (mostly updated locally, see
``operations/furniture/passage.py``).

A digest of the placements (every item's name, position and turn, over the seeds) is
printed per size, so a change meant to be faster only can be checked to place the same.

Target (issue 21): 128 items in ≤ 0.2 s CPU.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from cga.authoring import floor_from_rectangles, type_floor
from cga.operations.furniture.library import default_library
from cga.operations.furniture.passage import PASSAGE_WIDTH
from cga.operations.furniture.rules import load_furniture_rules
from cga.operations.furniture.solver import furnish_plan
from cga.resources import resolve_resource

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

TARGET_SECONDS = 0.2
COLUMNS = ("Room", "Name", "isInCorner", "isAlongWall", "hasPair", "PairWith",
           "minPairDistance", "maxPairDistance", "needInTurn", "clearanceSide",
           "clearanceFront", "clearanceBack", "canCloseWindow", "canBeAround", "nonCollision",
           "isDetail", "isOnTheSide")


def crowded_table(count: int, folder: Path) -> Path:
    """A rule table of ``count`` Livingroom items (thesis columns, tab-separated)."""
    lines = ["\t".join(COLUMNS)]
    for i in range(count):
        wall = i % 4 == 0
        name = f"bookshelf{i + 1}" if wall else f"chair{i + 1}"
        lines.append("\t".join(["Livingroom", name, "false", str(wall).lower(), "false",
                                "<null>", "0", "0", "false", "0.05", "0.05", "0", "false",
                                "false", "false", "false", "false"]))
    path = folder / f"crowded_{count}.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="16,32,64,128")
    parser.add_argument("--passage-width", type=float, default=PASSAGE_WIDTH)
    options = parser.parse_args()
    sizes = [int(s) for s in options.sizes.split(",")]
    plan = floor_from_rectangles([(0, 0, 16, 16)], windows_per_wall=1)
    plan = type_floor(plan, resolve_resource("thesis_types.csv", "rules"), seed=0)
    room = plan.rooms[0]
    plan = plan.with_changes(rooms=(room.__class__(room.id, room.polygon, room.interior,
                                                   "Livingroom"),))
    library = default_library()
    clock = ReferenceClock()
    rows = []
    with tempfile.TemporaryDirectory(prefix="cga-crowded-") as tmp:
        for count in sizes:
            rules = load_furniture_rules(crowded_table(count, Path(tmp)))
            models = {r.name: (library.get(r.name).name, library.get(r.name).size)
                      for r in rules if not r.is_detail}
            times, placed = [], []
            digest = hashlib.sha256()
            for seed in range(options.repeat):
                clock.sample()
                start = time.process_time()
                furniture, _ = furnish_plan(plan, rules, models, np.random.default_rng(seed),
                                            attempts=1, passage_width=options.passage_width)
                times.append(time.process_time() - start)
                placed.append(sum(not f.is_detail for f in furniture))
                digest.update(repr([(f.name, f.position, f.rotation)
                                    for f in furniture]).encode())
            rows.append((count, statistics.median(times), statistics.median(placed),
                         digest.hexdigest()[:16]))
    print(f"add_furniture, one 16 x 16 m room, {options.repeat} seeds per size, passage "
          f"width {options.passage_width:g} m; {clock.describe()}\n")
    print("| items | placed | median CPU s | / ref | growth exponent |")
    print("|---:|---:|---:|---:|---:|")
    previous = None
    for count, seconds, placed, _ in rows:
        growth = (f"{math.log(seconds / previous[1]) / math.log(count / previous[0]):.2f}"
                  if previous else "")
        print(f"| {count} | {placed:g} | {seconds:.3f} | {clock.ratio(seconds):,.0f} | {growth} |")
        previous = (count, seconds)
    print("\nplacements: " + ", ".join(f"{count} items {digest}"
                                      for count, _, _, digest in rows))
    last = rows[-1]
    if last[0] == 128:
        print(f"\n128 items: {last[1]:.3f} s CPU (target ≤ {TARGET_SECONDS} s: "
              f"{'met' if last[1] <= TARGET_SECONDS else 'not met'})")


if __name__ == "__main__":
    main()
