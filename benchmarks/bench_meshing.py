"""Benchmark: the meshing pass and the glb writer on furnished houses, CPU per house.

Builds ``--houses`` seeds of a grammar (default ``demos/house.grammar``) once, untimed,
then times, round after round, (a) the meshing pass (:func:`cga.meshing.scene_nodes`:
walls, slabs, stairs, posed furniture, dressing) and (b) writing the glb of the nodes
(:func:`cga.export.glb.scene_as_glb`), each over all the houses, with a sample of the
reference loop (``reference.py``) between rounds. Prints the minimum and the median CPU
milliseconds per house, the median in reference loops, and a digest of the glb files
(equal digests: equal bytes, e.g. before and after a change; run it with ``PYTHONPATH``
pointing at another checkout for the before figures).

    python benchmarks/bench_meshing.py [--repeats 7] [--houses 5] [--grammar FILE]
"""

from __future__ import annotations

import argparse
import hashlib
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

from cga.export.glb import scene_as_glb  # noqa: E402
from cga.meshing import scene_nodes  # noqa: E402
from cga.pipeline import build  # noqa: E402

DEFAULT_GRAMMAR = Path(__file__).resolve().parent.parent / "demos" / "house.grammar"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--houses", type=int, default=5)
    parser.add_argument("--grammar", type=Path, default=DEFAULT_GRAMMAR)
    args = parser.parse_args()

    scenes = [build(args.grammar, seed=seed, formats=(), physics=False, quiet=True)
              for seed in range(1, args.houses + 1)]
    files = [scene_as_glb(scene, scene.nodes) for scene in scenes]  # warm: models, tables
    clock = ReferenceClock()
    figures: dict[str, list[float]] = {"meshing": [], "glb": []}
    for _ in range(args.repeats):
        clock.sample()
        started = time.process_time()
        for scene in scenes:
            scene_nodes(scene)
        figures["meshing"].append((time.process_time() - started) / len(scenes))
        started = time.process_time()
        for scene in scenes:
            scene_as_glb(scene, scene.nodes)
        figures["glb"].append((time.process_time() - started) / len(scenes))

    nodes = statistics.median(len(scene.nodes) for scene in scenes)
    print(f"{args.grammar.name}: {args.houses} houses (seeds 1–{args.houses}), "
          f"{nodes:.0f} nodes (median), {args.repeats} rounds")
    print("| step | min ms/house | median ms/house | median / ref |")
    print("|---|---|---|---|")
    for name, values in figures.items():
        median = statistics.median(values)
        print(f"| {name} | {min(values) * 1e3:.1f} | {median * 1e3:.1f} | "
              f"{clock.ratio(median):.1f} |")
    print(clock.describe())
    print("glb digest", hashlib.sha1(b"".join(files)).hexdigest())


if __name__ == "__main__":
    main()
