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

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

__all__ = ["random_start", "separation_steering"]

_GOLDEN_ANGLE = np.pi * (3 - np.sqrt(5))

_FEW_ITEMS = 8
"""Up to this many items the rounds run on Python floats (:func:`_rounds_few`)."""


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
    Each round costs O(n²) for n items, all items moving at once; steering stops
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
    rounds = _rounds_few if n <= _FEW_ITEMS else _rounds_many
    return rounds(p, radii, movable, polygon, lo, hi, fallback, iterations,
                  (cohesion, separation, float(step_limit)))


_Weights = tuple[float, float, float]
"""``(cohesion, separation, step_limit)`` of :func:`separation_steering`."""


def _rounds_many(p: np.ndarray, radii: np.ndarray, movable: np.ndarray, polygon: Polygon,
                 lo: np.ndarray, hi: np.ndarray, fallback: np.ndarray, iterations: int,
                 weights: _Weights) -> np.ndarray:
    """The steering rounds on ``p`` (changed in place) with all items moving at once."""
    cohesion, separation, step_limit = weights
    n = len(p)
    reach = radii[:, None] + radii[None, :]
    diagonal = np.eye(n, dtype=bool)
    # the norms are written out as numpy.linalg.norm computes them and clips as the
    # maximum and minimum they are: the same floats with less overhead per call
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


def _rounds_few(p: np.ndarray, radii: np.ndarray, movable: np.ndarray, polygon: Polygon,
                lo: np.ndarray, hi: np.ndarray, fallback: np.ndarray, iterations: int,
                weights: _Weights) -> np.ndarray:
    """:func:`_rounds_many` in Python floats, for a few items (a house's rooms steer two
    to four).

    Each of its few dozen array operations would cost more in numpy's call overhead than
    the arithmetic, so the same operations are done on floats, in the order numpy does
    them: sums over items run from the first item to the last (numpy reduces a
    non-contiguous axis sequentially), an item's own term is ``+0.0``, and square roots,
    maxima and minima are exact, so the positions are the same floats
    (``tests/unit/furniture/test_furniture_steering.py`` compares the two).
    """
    cohesion, separation, step_limit = weights
    n = len(p)
    xs, zs = p[:, 0].tolist(), p[:, 1].tolist()
    r, fall, take_ok = radii.tolist(), fallback.tolist(), movable.tolist()
    (lox, loz), (hix, hiz) = lo.T.tolist(), hi.T.tolist()
    for _ in range(iterations):
        sum_x, sum_z = xs[0], zs[0]
        for k in range(1, n):
            sum_x += xs[k]
            sum_z += zs[k]
        new_x, new_z = [], []
        for i in range(n):
            push_x = push_z = 0.0
            for j in range(n):
                if j == i:
                    term_x = term_z = 0.0
                else:
                    dx, dz = xs[i] - xs[j], zs[i] - zs[j]
                    distance = math.sqrt(dx * dx + dz * dz)
                    if distance > 1e-9:
                        ux, uz = dx / distance, dz / distance
                    else:
                        ux, uz = fall[i]
                    overlap = r[i] + r[j] - distance
                    overlap = overlap if overlap >= 0.0 else 0.0
                    term_x, term_z = ux * overlap, uz * overlap
                if j == 0:
                    push_x, push_z = term_x, term_z
                else:
                    push_x += term_x
                    push_z += term_z
            vx = cohesion * ((sum_x - xs[i]) / (n - 1) - xs[i]) + separation * push_x
            vz = cohesion * ((sum_z - zs[i]) / (n - 1) - zs[i]) + separation * push_z
            speed = math.sqrt(vx * vx + vz * vz)
            scale = step_limit / (speed if speed >= 1e-12 else 1e-12)
            scale = 1.0 if 1.0 <= scale else scale
            x, z = xs[i] + vx * scale, zs[i] + vz * scale
            x, z = (x if x >= lox[i] else lox[i]), (z if z >= loz[i] else loz[i])
            new_x.append(x if x <= hix[i] else hix[i])
            new_z.append(z if z <= hiz[i] else hiz[i])
        inside = shapely.contains_xy(polygon, new_x, new_z).tolist()
        take = [ok and within for ok, within in zip(take_ok, inside)]
        if not any(t and (xs[i] != new_x[i] or zs[i] != new_z[i]) for i, t in enumerate(take)):
            break  # a fixed point: every further round would give the same positions
        xs = [x if t else old for x, old, t in zip(new_x, xs, take)]
        zs = [z if t else old for z, old, t in zip(new_z, zs, take)]
    return np.column_stack([xs, zs])
