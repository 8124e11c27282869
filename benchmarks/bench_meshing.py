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

import hashlib
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from per_house import build_houses, house_options, print_table, time_steps  # noqa: E402
from reference import ReferenceClock  # noqa: E402

from cga.export.glb import scene_as_glb  # noqa: E402
from cga.meshing import scene_nodes  # noqa: E402


def main() -> None:
    options = house_options(__doc__)
    scenes = build_houses(options, physics=False)
    files = [scene_as_glb(scene, scene.nodes) for scene in scenes]  # warm: models, tables
    figures = time_steps({
        "meshing": lambda: [scene_nodes(scene) for scene in scenes],
        "glb": lambda: [scene_as_glb(scene, scene.nodes) for scene in scenes],
    }, repeats=options.repeats, houses=len(scenes), clock=(clock := ReferenceClock()))
    nodes = statistics.median(len(scene.nodes) for scene in scenes)
    print(f"{options.grammar.name}: {options.houses} houses (seeds 1–{options.houses}), "
          f"{nodes:.0f} nodes (median), {options.repeats} rounds")
    print_table(figures, clock)
    print("glb digest", hashlib.sha1(b"".join(files)).hexdigest())


if __name__ == "__main__":
    main()
