"""Survey the stairs of the multi-storey demos over many seeds (DESIGN §12, issue 13).

For every seed of every multi-storey demo, the storeys are derived and stacked and the
stairs checked against what a user expects, from the meshes and plans rather than from
the stair code's own bookkeeping:

* one stair per pair of consecutive floors, ``is_top`` on the top floor only;
* the hole in the upper slab's mesh (its walking surface seen from above) matches the
  stair's outline: IoU ≥ 0.99;
* the stair and its landings lie in a circulation room on both floors;
* rise ≤ max_rise, going ≥ min_going, width ≥ the stair width asked for, and the risers
  add up to the storey height.

With ``--full N`` the first N seeds of each demo are also built with furniture and
checked (physics and navigability from the front door through the stairs at 0.25 m).
The structural survey replaces ``add_furniture`` by a pass-through (furniture does not
move stairs), so 300 seeds take a minute or two.

Usage::

    python benchmarks/survey_stairs.py --seeds 300 --full 20 [--demo house ...]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from shapely.geometry import Polygon
from shapely.ops import unary_union

from cga.building import stack_storeys
from cga.evaluator import Evaluator
from cga.registry import OperationRegistry
from cga.operation import Child, Operation, OperationContext, Param
from cga.meshing.solids import floor_nodes
from cga.parser import parse, read_grammar
from cga.pipeline import build
from cga.shape import Shape

ROOT = Path(__file__).resolve().parents[1]
DEMOS = {"house": (0.19, 0.25, 1.0), "office": (0.19, 0.25, 1.0),
         "apartment_block": (0.18, 0.27, 1.1)}


class _NoFurniture(Operation):
    """add_furniture's signature, passing the floor through unfurnished."""

    name = "add_furniture"
    params = tuple(Param(n, k) for n, k in (
        ("rules", "string"), ("windows", "tuple"), ("doorWidth", "length"),
        ("doorHeight", "length"), ("steeringIterations", "count"), ("clearanceTries", "count")))

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        return [Child(successor=0, geometry=shape.geometry, scope=shape.scope, plan=shape.plan)]


def _walking_surface(node) -> Any:
    mesh = node.mesh
    top = mesh.triangles[mesh.face_normals[:, 1] > 0.99][:, :, [0, 2]]
    return unary_union([Polygon(t).buffer(1e-7) for t in top])


def structural_problems(plans: list, limits: tuple[float, float, float]) -> list[str]:
    max_rise, min_going, width = limits
    problems = []
    plans = sorted(plans, key=lambda p: p.index)
    stairs = {s.id: s for p in plans for s in p.stairs}
    pairs = sorted(s.floors for s in stairs.values())
    if pairs != [(p.index, p.index + 1) for p in plans[:-1]]:
        problems.append(f"stairs join {pairs}")
    if [p.is_top for p in plans] != [False] * (len(plans) - 1) + [True]:
        problems.append("is_top wrong")
    by_index = {p.index: p for p in plans}
    for stair in stairs.values():
        upper = by_index[stair.floors[1]]
        slab = next(n for n in floor_nodes(upper) if n.kind == "slab")
        surface = _walking_surface(slab)
        holes = [Polygon(h) for g in getattr(surface, "geoms", [surface]) for h in g.interiors]
        if len(holes) != 1:
            problems.append(f"stair {stair.id}: {len(holes)} holes in the slab above")
        else:
            iou = holes[0].intersection(stair.polygon).area / holes[0].union(stair.polygon).area
            if iou < 0.99:
                problems.append(f"stair {stair.id}: IoU {iou:.3f}")
        for floor in stair.floors:
            plan = by_index[floor]
            rooms = [r for r in plan.rooms if r.polygon.buffer(1e-6).covers(stair.polygon)]
            if not rooms or not all(r.circulation for r in rooms):
                problems.append(f"stair {stair.id} not in circulation on floor {floor}")
        if stair.rise > max_rise + 1e-9 or stair.going < min_going - 1e-9 or stair.width < width - 1e-9:
            problems.append(f"stair {stair.id}: rise {stair.rise:.4f} going {stair.going:.4f} "
                            f"width {stair.width:.2f}")
        if abs(stair.risers * stair.rise - (stair.top_y - stair.bottom_y)) > 1e-6:
            problems.append(f"stair {stair.id}: risers do not add up")
    return problems


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=300)
    parser.add_argument("--full", type=int, default=0, help="seeds also built with checks")
    parser.add_argument("--demo", action="append", choices=sorted(DEMOS),
                        help="survey only this demo (repeatable; default: all)")
    args = parser.parse_args()
    registry = OperationRegistry()
    registry.register(_NoFurniture())
    for name, limits in DEMOS.items():
        if args.demo and name not in args.demo:
            continue
        path = ROOT / "demos" / f"{name}.grammar"
        grammar = parse(read_grammar(path), str(path))
        started, bad, storeys = time.perf_counter(), {}, set()
        for seed in range(args.seeds):
            try:
                derivation = Evaluator(grammar, seed=seed, operations=registry,
                                       base_dir=path.parent).derive()
                plans = [s.plan for s in stack_storeys(derivation.terminals) if s.plan]
                storeys.add(len(plans))
                problems = structural_problems(plans, limits)
            except Exception as error:  # noqa: BLE001 - a survey reports every failure
                problems = [f"{type(error).__name__}: {error}"]
            if problems:
                bad[seed] = problems
        print(f"{name}: {args.seeds - len(bad)}/{args.seeds} seeds pass the stair checks "
              f"(storeys {sorted(storeys)}, {time.perf_counter() - started:.0f} s)")
        for seed, problems in list(bad.items())[:10]:
            print(f"  seed {seed}: {'; '.join(problems)}")
        failed = {}
        for seed in range(args.full):
            scene = build(path, seed=seed, formats=(), quiet=True)
            failing = [report for report in scene.checks.values() if not report.passed]
            if failing:
                failed[seed] = [report.summary() for report in failing]
        if args.full:
            print(f"  full builds: {args.full - len(failed)}/{args.full} pass physics and "
                  f"navigability (front door → stairs → every room, r = 0.25 m)")
            for seed, summaries in failed.items():
                print(f"  seed {seed}: {' | '.join(summaries)}")


if __name__ == "__main__":
    main()
