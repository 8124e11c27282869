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

import dataclasses
import hashlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from per_house import build_houses, house_options, print_table, time_steps  # noqa: E402
from reference import ReferenceClock  # noqa: E402

import cga  # noqa: E402
from cga.export.drawing import render_png, render_svg  # noqa: E402
from cga.export.plan import plan_drawing  # noqa: E402
from cga.export.scene_json import scene_json_text  # noqa: E402


def main() -> None:
    options = house_options(__doc__)
    scenes = [dataclasses.replace(scene, timings={})
              for scene in build_houses(options, physics=False)]
    floors = [plan for scene in scenes for plan in scene.floors]
    texts = [scene_json_text(scene, scene.nodes) for scene in scenes]  # warm: nodes, fonts
    drawings = [plan_drawing(plan, title=f"floor {plan.index}") for plan in floors]
    plans = [render_svg(d).encode() + render_png(d) for d in drawings]
    figures = time_steps({
        "scene JSON": lambda: [scene_json_text(scene, scene.nodes) for scene in scenes],
        "plan drawing": lambda: [plan_drawing(plan, title=f"floor {plan.index}")
                                 for plan in floors],
        "plan SVG": lambda: [render_svg(d) for d in drawings],
        "plan PNG": lambda: [render_png(d) for d in drawings],
    }, repeats=options.repeats, houses=len(scenes), clock=(clock := ReferenceClock()))
    print(f"{options.grammar.name}: {options.houses} houses (seeds 1–{options.houses}), "
          f"{len(floors) / len(scenes):.1f} floors per house, {options.repeats} rounds")
    print_table(figures, clock)
    checkout = str(Path(cga.__file__).resolve().parent.parent)
    text = "".join(texts).replace(checkout, "")
    print("scene JSON digest", hashlib.sha1(text.encode()).hexdigest())
    print("plan digest", hashlib.sha1(b"".join(plans)).hexdigest())


if __name__ == "__main__":
    main()
