"""type_rooms over many random floors and tables: every promise checked independently.

Floors are random guillotine tilings of a random rectangle (1–12 rooms, sides ≥ 3 m)
built with ``plan_from_rectangles`` (600 seeds), and make_floor's BSP partitions of
rectangle, L, U and T footprints (300 seeds); tables are the shipped ones plus random
tables whose sizes and neighbour lists are drawn per seed, so failures happen too. For
every floor,
either the typed plan passes ``validate_typed_plan`` (tests/support/typing_checks.py:
shapely + networkx, independent of the typing code), or a NoSolutionError says which
rule failed and why.
"""


import numpy as np

from cga.errors import NoSolutionError
from cga.model import FloorSettings
from cga.operations.floorplan.assemble import plan_from_dcel
from cga.operations.floorplan.bsp import partition
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.roomtyping.rules import load_rule_table
from cga.operations.type_rooms import type_plan
from cga.resources import resolve_resource

from typing_checks import validate_typed_plan

SEEDS = 600
MIN_SIDE = 3.0
TYPES = ["Livingroom", "Kitchen", "Bedroom", "Bathroom", "Hall", "Office", "Storageroom"]


def random_rectangles(rng, rooms):
    """A guillotine tiling: split the largest splittable leaf at a random position."""
    leaves = [(0.0, 0.0, round(float(rng.uniform(8, 22)), 2), round(float(rng.uniform(6, 14)), 2))]
    while len(leaves) < rooms:
        leaves.sort(key=lambda r: (r[2] - r[0]) * (r[3] - r[1]), reverse=True)
        for k, (x0, z0, x1, z1) in enumerate(leaves):
            axes = [0, 1] if x1 - x0 >= z1 - z0 else [1, 0]
            axis = next((a for a in axes if (x1 - x0, z1 - z0)[a] >= 2 * MIN_SIDE), None)
            if axis is None:
                continue
            lo, hi = (x0, x1) if axis == 0 else (z0, z1)
            cut = round(float(rng.uniform(lo + MIN_SIDE, hi - MIN_SIDE)), 2)
            pieces = ([(x0, z0, cut, z1), (cut, z0, x1, z1)] if axis == 0 else
                      [(x0, z0, x1, cut), (x0, cut, x1, z1)])
            leaves[k:k + 1] = pieces
            break
        else:
            break
    return leaves


def random_table(rng, folder, mean_area):
    """A random thesis-format table: 2–5 mandatory rules, some optional ones."""
    count = int(rng.integers(3, len(TYPES) + 1))
    names = list(rng.permutation(TYPES)[:count])
    mandatory = int(rng.integers(2, min(count, 5) + 1))
    lines = ["Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom"]
    for k, name in enumerate(names):
        listed = [n for n in names if n != name and rng.random() < 0.5] or [names[k - 1]]
        size = round(float(rng.uniform(0.1, 1.3)) * mean_area, 1)
        lines.append(f"{name};{size};{rng.random():.2f};{', '.join(listed)};{int(k == 0)};"
                     f"{int(rng.integers(1, 3))};{int(k >= mandatory)}")
    path = folder / "random_types.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_typing_promises_hold_on_random_floors(tmp_path):
    shipped = [resolve_resource(f"{n}_types.csv", "rules") for n in ("house", "office", "thesis")]
    failures, typed_floors, refused = [], 0, 0
    for seed in range(SEEDS):
        rng = np.random.default_rng(seed)
        rects = random_rectangles(rng, int(rng.integers(1, 13)))
        index = 1 if seed % 5 == 4 else 0
        plan = plan_from_rectangles(rects, index=index)
        if seed % 4 == 3:
            path = random_table(rng, tmp_path, plan.footprint.area / len(rects))
        else:
            path = shipped[seed % 3]
        table = load_rule_table(path)
        try:
            typed = type_plan(plan, table, rng, door_position=("center", "random")[seed % 2])
        except NoSolutionError as error:
            refused += 1
            text = str(error)
            if not (error.reasons and "m²" in text
                    and any(r.type in text for r in table.mandatory)):
                failures.append((seed, f"unclear refusal: {text}"))
            continue
        typed_floors += 1
        try:
            validate_typed_plan(typed, path, front_door=(index == 0 and table.outside_rule is not None))
        except AssertionError as error:
            failures.append((seed, str(error)))
    assert not failures, failures[:5]
    # both outcomes exercised; the shipped house and office tables enter every room from a
    # hall, which these corridor-less floors often lack, so they refuse more floors
    assert typed_floors >= SEEDS * 0.55 and refused > 0


SHARE_TYPED_WITHOUT_HALL = 0.15
"""Share of these hall-less floors the shipped access tables still type (54 of 300 seen)."""

FOOTPRINTS = {
    "rectangle": [(0, 0), (14, 0), (14, 10), (0, 10)],
    "L": [(0, 0), (16, 0), (16, 7), (8, 7), (8, 13), (0, 13)],
    "U": [(0, 0), (18, 0), (18, 12), (12, 12), (12, 6), (6, 6), (6, 12), (0, 12)],
    "T": [(0, 6), (6, 6), (6, 0), (12, 0), (12, 6), (18, 6), (18, 12), (0, 12)],
}


def test_typing_promises_hold_on_make_floor_partitions():
    """The same promises on floors cut by make_floor's BSP (any rectilinear footprint)."""
    shipped = [resolve_resource(f"{n}_types.csv", "rules") for n in ("house", "office")]
    tables = [load_rule_table(path) for path in shipped]
    failures, typed_floors, refused = [], 0, 0
    for seed in range(300):
        rng = np.random.default_rng(10_000 + seed)
        name = list(FOOTPRINTS)[seed % len(FOOTPRINTS)]
        settings = FloorSettings(windows_per_wall=1 + seed % 2)
        result = partition(FOOTPRINTS[name], int(rng.integers(2, 10)), rng)
        plan = plan_from_dcel(result.dcel, settings=settings, index=int(seed % 3 == 2),
                              elevation=0.0, height=3.0)
        try:
            typed = type_plan(plan, tables[seed % 2], rng)
        except NoSolutionError as error:
            refused += 1
            if not error.reasons:  # a refusal says why
                failures.append((seed, name, f"unexplained refusal: {error}"))
            continue
        typed_floors += 1
        try:
            validate_typed_plan(typed, shipped[seed % 2], front_door=plan.index == 0)
        except AssertionError as error:
            failures.append((seed, name, str(error)))
    assert not failures, failures[:5]
    # these partitions have no hall or corridor, which the shipped tables enter every
    # room from, so some are refused (with reasons); most still type
    assert typed_floors >= SHARE_TYPED_WITHOUT_HALL * 300
