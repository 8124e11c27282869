"""Start positions for furniture: random draws spread out by separation steering.

Before any rule is applied, each item gets a random position in its room and a few
rounds of Reynolds' steering spread the items out (thesis §3.4, appendix algorithms 14
and 15). Only two of the three boid behaviours are used: *cohesion* pulls an item
towards the centre of the others, *separation* pushes apart items whose bounding
circles overlap. The resulting positions decide which wall or corner each item tries
first and where free-standing items stand, so varied starts give varied layouts.

Items that go into a corner do not take part (the thesis excludes them), nor do
children (placed relative to their parent) and non-colliding items (rugs).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon

__all__ = ["random_start", "separation_steering"]

_GOLDEN_ANGLE = np.pi * (3 - np.sqrt(5))


def _centre_bounds(polygon: Polygon, half_extents: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per item, the box its centre may range over to keep its footprint in the bounds
    (the bounds' centre when the item is larger than the room)."""
    half = np.asarray(half_extents, dtype=float).reshape(-1, 2)
    minx, minz, maxx, maxz = polygon.bounds
    lo = np.array([minx, minz]) + half
    hi = np.array([maxx, maxz]) - half
    centre = np.array([(minx + maxx) / 2, (minz + maxz) / 2])
    fits = lo <= hi
    return np.where(fits, lo, centre), np.where(fits, hi, centre)


def random_start(polygon: Polygon, half_extents: np.ndarray, rng: np.random.Generator,
                 *, attempts: int = 8) -> np.ndarray:
    """Random centres inside ``polygon`` for items of the given half extents.

    Parameters
    ----------
    polygon:
        The room's free floor.
    half_extents:
        ``(n, 2)`` half sizes along x and z; an item too big for the room is centred.
    rng:
        The random stream.
    attempts:
        Redraws for centres that fall outside a non-rectangular polygon; the rest go to
        a point inside the polygon.

    Returns
    -------
    numpy.ndarray
        ``(n, 2)`` centres.
    """
    lo, hi = _centre_bounds(polygon, half_extents)
    points = rng.uniform(lo, hi)
    for _ in range(attempts):
        outside = ~shapely.contains_xy(polygon, points[:, 0], points[:, 1])
        if not outside.any():
            return points
        points[outside] = rng.uniform(lo[outside], hi[outside])
    inside_point = polygon.representative_point()
    outside = ~shapely.contains_xy(polygon, points[:, 0], points[:, 1])
    points[outside] = (inside_point.x, inside_point.y)
    return points


def separation_steering(positions: np.ndarray, radii: np.ndarray, movable: np.ndarray,
                        polygon: Polygon, half_extents: np.ndarray, iterations: int, *,
                        cohesion: float = 0.05, separation: float = 0.5,
                        max_step: float | None = None) -> np.ndarray:
    """Spread items apart with Reynolds' cohesion and separation.

    Parameters
    ----------
    positions:
        ``(n, 2)`` start centres.
    radii:
        ``(n,)`` radius of each item's bounding circle.
    movable:
        ``(n,)`` booleans; items that do not move still repel and attract the others.
    polygon:
        The room's free floor; a step that would leave it is not taken.
    half_extents:
        ``(n, 2)`` half sizes; centres stay at least this far inside the room's bounds.
    iterations:
        Rounds of steering (the grammar's ``steeringIterations``).
    cohesion, separation:
        Weights of the two behaviours.
    max_step:
        Longest move per round (default: a tenth of the room's bounding-box diagonal).

    Returns
    -------
    numpy.ndarray
        ``(n, 2)`` new centres (the input is not modified).

    Notes
    -----
    Each round costs O(n²) for n items, all items moving at once (numpy); steering stops
    early at a fixed point (no item moves), which rounds after it would not change. Coincident
    items are pushed apart along a fixed, index-dependent direction, so the result is
    a pure function of the input.

    References
    ----------
    C. W. Reynolds, "Flocks, herds and schools: a distributed behavioral model",
    SIGGRAPH 1987.
    """
    p = np.array(positions, dtype=float).reshape(-1, 2)
    n = len(p)
    movable = np.asarray(movable, dtype=bool)
    if n < 2 or iterations <= 0 or not movable.any():
        return p
    radii = np.asarray(radii, dtype=float)
    lo, hi = _centre_bounds(polygon, half_extents)
    minx, minz, maxx, maxz = polygon.bounds
    step_limit = max_step if max_step is not None else 0.1 * np.hypot(maxx - minx, maxz - minz)
    angles = _GOLDEN_ANGLE * np.arange(n)
    fallback = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    reach = radii[:, None] + radii[None, :]
    diagonal = np.eye(n, dtype=bool)
    # The rooms hold a handful of items, so each round is a few dozen tiny array
    # operations and numpy's call overhead dominates: the norms are written out as
    # numpy.linalg.norm computes them and clips as the maximum and minimum they are,
    # which gives the same floats with less overhead.
    for _ in range(iterations):
        delta = p[:, None, :] - p[None, :, :]  # i minus j
        distance = np.sqrt(np.add.reduce(delta * delta, axis=2))
        distance[diagonal] = np.inf  # so an item neither pushes itself nor overlaps
        apart = distance > 1e-9
        if apart.all():
            direction = delta / distance[..., None]
        else:
            direction = np.where(apart[..., None],
                                 delta / np.where(apart, distance, 1.0)[..., None],
                                 fallback[:, None, :])
        overlap = np.maximum(reach - distance, 0.0)
        push = np.add.reduce(direction * overlap[..., None], axis=1)
        pull = (np.add.reduce(p, axis=0) - p) / (n - 1) - p
        velocity = cohesion * pull + separation * push
        speed = np.sqrt(np.add.reduce(velocity * velocity, axis=1, keepdims=True))
        velocity *= np.minimum(1.0, step_limit / np.maximum(speed, 1e-12))
        proposal = np.minimum(np.maximum(p + velocity, lo), hi)
        inside = shapely.contains_xy(polygon, proposal[:, 0], proposal[:, 1])
        take = (movable & inside)[:, None]
        if not ((p != proposal) & take).any():
            break  # a fixed point: every further round would give the same positions
        np.copyto(p, proposal, where=take)
    return p
