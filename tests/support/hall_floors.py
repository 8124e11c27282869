"""Random house and office floors for the furniture property tests and measurements:
a hall along the middle of a rectangle, rooms 2–6 m wide cut across its two sides."""

from __future__ import annotations

import numpy as np

__all__ = ["HALL", "KINDS", "typed_hall_floor", "with_hall"]

KINDS = {"house": ("house_types.csv", "furniture_house.csv", (10, 15), (8, 11), (3, 7)),
         "office": ("office_types.csv", "furniture_office.csv", (14, 20), (10, 14), (5, 9))}
"""Kind → (typing table, furniture table, width range, depth range, room count range)."""

HALL = 1.8  # the shipped tables enter every room from a hall or corridor


def with_hall(rng: np.random.Generator, width: tuple, depth: tuple
              ) -> list[tuple[float, float, float, float]]:
    """A hall along the middle of a random rectangle (room 0), rooms 2–6 m wide cut
    across the two sides."""
    w, d = round(rng.uniform(*width), 1), round(rng.uniform(*depth), 1)
    z0 = round((d - HALL) / 2, 2)
    pieces = [(0.0, z0, w, z0 + HALL)]
    for lo, hi in ((0.0, z0), (z0 + HALL, d)):
        x = 0.0
        while w - x >= 4.0:
            step = round(min(rng.uniform(2.0, 6.0), w - x - 2.0), 2)
            pieces.append((x, lo, x + step, hi))
            x += step
        pieces.append((x, lo, w, hi))
    return pieces


def typed_hall_floor(kind: str, seed: int):
    """A random floor of ``kind`` (:data:`KINDS`) drawn from ``seed``, typed by its
    shipped table with the same seed, and the furniture table that goes with it; None
    when the table cannot type that floor."""
    from cga.authoring import floor_from_rectangles, type_floor
    from cga.errors import NoSolutionError

    types, table, width, depth, _ = KINDS[kind]
    rng = np.random.default_rng(seed)
    plan = floor_from_rectangles(with_hall(rng, width, depth), windows_per_wall=2,
                                 circulation=[0])
    try:
        return type_floor(plan, types, seed=seed), table
    except NoSolutionError:
        return None
