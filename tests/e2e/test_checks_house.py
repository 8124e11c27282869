"""End to end: the furnished house demo over many seeds, through its physics and
navigability checks.

Each seed is built exactly as ``cga build`` does (checks included, no files written), on
two worker processes. Physics must be clean on every seed: no item overlapping anything
by more than 5 mm, none moving more than 1 cm. Navigability may fail (furniture can wall
a room off), but then the report must say which rooms and why, and the share of seeds
with every room reachable is printed. An independent checker (exact shapely geometry
instead of the check's grid) confirms the rooms reported reachable: every room that a
robot more cautious than the check's reaches, the check must report reachable too.

The check's settle stops once every item has rested for 0.1 s (see
``cga.checks.physics``), so the short settle needs no special setting here. The seed
count can be changed with ``CGA_CHECK_SEEDS`` (default 200).
"""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor

import pytest
from house_checks import RADIUS, run_seed

pytestmark = [pytest.mark.slow, pytest.mark.physics]

SEEDS = int(os.environ.get("CGA_CHECK_SEEDS", "200"))


@pytest.fixture(scope="module")
def results() -> list[dict]:
    context = multiprocessing.get_context("spawn")  # see house_checks' notes
    with ProcessPoolExecutor(max_workers=2, mp_context=context) as pool:
        return list(pool.map(run_seed, range(SEEDS), chunksize=4))


def test_house_is_furnished(results):
    assert all(r["items"] >= 20 for r in results), [r["items"] for r in results]


def test_no_item_overlaps_or_moves(results):
    bad = [(r["seed"], item) for r in results for item in r["bad_items"]]
    problems = sum(len(r["physics_problems"]) for r in results)
    print(f"\nphysics: {len(results)} seeds, {sum(r['items'] for r in results)} items, "
          f"{len(bad)} overlapping > 5 mm or moving > 1 cm, {problems} with any problem")
    assert not bad, bad[:10]


def test_unreachable_rooms_are_named_with_reasons(results):
    complete = sum(r["passed"] for r in results)
    print(f"\nnavigability (radius {RADIUS} m): every room reachable in {complete}/{len(results)} "
          f"seeds ({100 * complete / len(results):.1f} %)")
    for r in results:
        for floor in r["floors"]:
            unreachable = [room["room"] for room in floor["unreachable"]]
            assert sorted(floor["reachable"] + unreachable) == floor["rooms"], (r["seed"], floor)
            for room in floor["unreachable"]:
                assert room["reasons"], (r["seed"], floor["floor"], room)
                for door in room["blocked_doors"]:
                    assert room["room"] in floor["doors"][door], (r["seed"], room)
                assert set(room["blocking_items"]) <= r["furniture"], (r["seed"], room)
            if unreachable:
                print(f"  seed {r['seed']} floor {floor['floor']}: " + "; ".join(
                    f"room {room['room']} ({room['type']}): {' / '.join(room['reasons'])}"
                    for room in floor["unreachable"]))


def test_rooms_a_cautious_robot_reaches_are_reported_reachable(results):
    missed = [(r["seed"], f["floor"], sorted(set(f["cautious"]) - set(f["reachable"])))
              for r in results for f in r["floors"] if set(f["cautious"]) - set(f["reachable"])]
    assert not missed, missed[:10]
