"""Benchmark: the scene JSON and the floor plans of furnished houses, CPU per house.

Builds ``--houses`` seeds of a grammar (default ``demos/house.grammar``) once, untimed,
then times, round after round and each over all the houses: (a) the scene JSON text
(:func:`cga.export.scene_json.scene_json_text`), (b) composing every floor's plan
(:func:`cga.export.plan.plan_drawing`), (c) its SVG and (d) its PNG
(:mod:`cga.export.drawing`), with a sample of the reference loop (``reference.py``)
between rounds. Files are not written (``cga/fsutil.py`` is timed by the whole build).
Prints the minimum and the median CPU milliseconds per house, the median in reference
loops, and digests of the JSON text (``timings`` left out, the checkout's folder, which
diagnostics name with the shipped tables, cut from the text) and of the plan files
(equal digests: equal bytes, e.g. before and after a change; run it with
``PYTHONPATH`` pointing at another checkout for the before figures).

    python benchmarks/bench_exports.py [--repeats 7] [--houses 5] [--grammar FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

import cga  # noqa: E402
from cga.export.drawing import render_png, render_svg  # noqa: E402
from cga.export.plan import plan_drawing  # noqa: E402
from cga.export.scene_json import scene_json_text  # noqa: E402
from cga.pipeline import build  # noqa: E402

DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--houses", type=int, default=5)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    args = parser.parse_args()

    scenes = [dataclasses.replace(build(args.grammar, seed=seed, formats=(), physics=False,
                                        quiet=True), timings={})
              for seed in range(1, args.houses + 1)]
    floors = [plan for scene in scenes for plan in scene.floors]
    texts = [scene_json_text(scene, scene.nodes) for scene in scenes]  # warm: nodes, fonts
    drawings = [plan_drawing(plan, title=f"floor {plan.index}") for plan in floors]
    plans = [render_svg(d).encode() + render_png(d) for d in drawings]
    clock = ReferenceClock()
    steps = {
        "scene JSON": lambda: [scene_json_text(scene, scene.nodes) for scene in scenes],
        "plan drawing": lambda: [plan_drawing(plan, title=f"floor {plan.index}")
                                 for plan in floors],
        "plan SVG": lambda: [render_svg(d) for d in drawings],
        "plan PNG": lambda: [render_png(d) for d in drawings],
    }
    figures: dict[str, list[float]] = {name: [] for name in steps}
    for _ in range(args.repeats):
        clock.sample()
        for name, step in steps.items():
            started = time.process_time()
            step()
            figures[name].append((time.process_time() - started) / len(scenes))

    print(f"{args.grammar.name}: {args.houses} houses (seeds 1–{args.houses}), "
          f"{len(floors) / len(scenes):.1f} floors per house, {args.repeats} rounds")
    print("| step | min ms/house | median ms/house | median / ref |")
    print("|---|---|---|---|")
    for name, values in figures.items():
        median = statistics.median(values)
        print(f"| {name} | {min(values) * 1e3:.1f} | {median * 1e3:.1f} | "
              f"{clock.ratio(median):.1f} |")
    print(clock.describe())
    checkout = str(Path(cga.__file__).resolve().parent.parent)
    text = "".join(texts).replace(checkout, "")
    print("scene JSON digest", hashlib.sha1(text.encode()).hexdigest())
    print("plan digest", hashlib.sha1(b"".join(plans)).hexdigest())


if __name__ == "__main__":
    main()
