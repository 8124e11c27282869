"""Measure the plans of the shipped demos over many seeds (DESIGN §11).

    python scripts/plan_quality.py [--seeds 300] [--demos house,apartment,...]

Each demo is derived without its furniture rule (the layout comes before it) and every
floor is read through the layout-quality report (:mod:`cga.quality`) and the rule
tables: private rooms that are the only way into another room (en-suite rooms that list
the private type in ``enteredFrom`` are counted apart), offices and meeting rooms
without a door onto circulation, front doors not into circulation, rule-less rooms,
median areas of bathrooms and bedrooms, median doors of living rooms, floors re-drawn.
Also the thesis' typing grammar on a 20 m x 20 m lot at units = 10.
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from cga.errors import CGAError
from cga.evaluator import Evaluator
from cga.lot import parse_lot
from cga.parser import parse
from cga.quality import floor_quality
from cga.scene import Scene
from cga.operations.roomtyping.rules import load_rule_table

ROOT = Path(__file__).resolve().parents[1]
DEMOS = ("house", "apartment", "office", "office_corridor", "office_wings")


def floors(text: str, name: str, seed: int, base: Path, units: float | None = None,
           lot: str | None = None):
    derivation = Evaluator(parse(text, f"{name}.grammar"), seed=seed, units=units,
                           base_dir=base).derive(parse_lot(lot) if lot else None)
    scene = Scene(name=name, seed=seed, units=derivation.units, terminals=derivation.terminals)
    return scene.floors


def measure_demo(name: str, seeds: int) -> None:
    text = (ROOT / "demos" / f"{name}.grammar").read_text()
    text = re.sub(r"^Typed --> add_furniture\(.*$", "", text, flags=re.M)
    tables = {m: load_rule_table(ROOT / "rules" / m)
              for m in set(re.findall(r'type_rooms\("([^"]+)"', text))}
    failures = through_private = en_suite = not_on_corridor = bad_front = ruleless = 0
    redrawn = floor_count = 0
    areas: dict[str, list[float]] = {}
    living_doors: list[int] = []
    start = time.perf_counter()
    for seed in range(seeds):
        try:
            plans = floors(text, name, seed, ROOT / "demos")
        except CGAError:
            failures += 1
            continue
        for plan in plans:
            floor_count += 1
            table = next(t for t in tables.values()
                         if all(t.rule_for(r.type) or r.type == "Commonroom" for r in plan.rooms))
            report = floor_quality(plan)
            types = {r.id: r.type for r in plan.rooms}
            for entry in report["pass_through_private"]:
                for room in entry["behind"]:
                    rule = table.rule_for(types[room])
                    allowed = rule is not None and types[entry["room"]] in (rule.entered_from or ())
                    en_suite += allowed
                    through_private += not allowed
            ruleless += len(report["ruleless"])
            redrawn += any("re-drew" in d.message for d in plan.diagnostics)
            circulation = {r.id for r in plan.rooms if r.circulation}
            for r in plan.rooms:
                areas.setdefault(r.type, []).append(r.area)
                doors = [d for d in plan.doors if r.id in d.rooms]
                if r.type == "Livingroom":
                    living_doors.append(len(doors))
                if r.type in ("Office", "Meetingroom") and not any(
                        set(d.rooms) & circulation for d in doors):
                    not_on_corridor += 1
            front = plan.front_door()
            if plan.index == 0 and circulation and (front is None or front.swing_room not in circulation):
                bad_front += 1
    med = lambda k: f"{statistics.median(areas[k]):.1f}" if k in areas else "-"
    print(f"| {name} | {seeds} | {failures} | {floor_count} | {redrawn} | {through_private} | "
          f"{en_suite} | {not_on_corridor} | {bad_front} | {ruleless} | {med('Bathroom')} | "
          f"{med('Bedroom')} | {statistics.median(living_doors) if living_doors else '-'} | "
          f"{(time.perf_counter() - start) / max(seeds, 1):.2f} |")


def measure_thesis(seeds: int) -> None:
    work = Path(tempfile.mkdtemp())
    shutil.copy(ROOT / "rules" / "thesis_types.csv", work / "TestConfig.csv")
    text = (ROOT / "tests" / "data" / "thesis" / "figure_6_5_typing.grammar").read_text()
    for label, variant in (("random cuts + re-draws", text),
                           ("thesis mode", text.replace("doorWidth,doorHeight) Floor1",
                                                        "doorWidth,doorHeight, cut_range = (0.5, 0.5)) Floor1"))):
        typed = 0
        for seed in range(seeds):
            try:
                plans = floors(variant, "thesis", seed, work, units=10, lot="20x20")
            except CGAError:
                continue
            mandatory = {"Livingroom", "Kitchen", "Bedroom", "Bathroom"}
            typed += all(mandatory <= {r.type for r in p.rooms} for p in plans)
        print(f"thesis TestConfig.csv, 20 m x 20 m, units = 10, {label}: typed {typed} of {seeds}")
    shutil.rmtree(work, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=300)
    parser.add_argument("--demos", default=",".join(DEMOS))
    parser.add_argument("--thesis-seeds", type=int, default=200)
    options = parser.parse_args()
    print("| demo | seeds | failed | floors | re-drawn | private only way in | en-suite | "
          "office/meeting not on circulation | front door not into circulation | rule-less | "
          "median bathroom m² | median bedroom m² | median living-room doors | s/seed |")
    print("|---|" + "---:|" * 13)
    for name in options.demos.split(","):
        if name:
            measure_demo(name, options.seeds)
    if options.thesis_seeds:
        measure_thesis(options.thesis_seeds)


if __name__ == "__main__":
    main()
