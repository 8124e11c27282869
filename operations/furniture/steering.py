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
from collections.abc import Callable
from functools import reduce
from operator import add

import numpy as np
import shapely
from shapely.geometry import Polygon

__all__ = ["Flock"]

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


class Flock:
    """Items of one room to start apart: random centres (:meth:`random_start`) spread
    by Reynolds' cohesion and separation (:meth:`steer`).

    Parameters
    ----------
    polygon:
        The room's free floor; a centre outside it is drawn again, a step that would
        leave it is not taken.
    half_extents:
        ``(n, 2)`` half sizes along x and z; centres stay at least this far inside the
        room's bounds, and an item too big for the room is centred.
    radii:
        ``(n,)`` radius of each item's bounding circle.
    movable:
        ``(n,)`` booleans; items that do not move still repel and attract the others.
    cohesion, separation:
        Weights of the two behaviours.
    max_step:
        Longest move per round (default: a tenth of the room's bounding-box diagonal).

    Notes
    -----
    The solver starts a room's items afresh at every attempt: the same items in the same
    room, so all that does not depend on the random draws is made here, once per room
    (numpy's cost per call on arrays of a few items and shapely's per attribute came to
    a third of what the starts cost).

    References
    ----------
    C. W. Reynolds, "Flocks, herds and schools: a distributed behavioral model",
    SIGGRAPH 1987.
    """

    def __init__(self, polygon: Polygon, half_extents: np.ndarray, radii: np.ndarray,
                 movable: np.ndarray, *, cohesion: float = 0.05, separation: float = 0.5,
                 max_step: float | None = None):
        self.polygon = polygon
        half = np.asarray(half_extents, dtype=float).reshape(-1, 2)
        self.radii = np.asarray(radii, dtype=float)
        self.movable = np.asarray(movable, dtype=bool)
        self.lo, self.hi = _centre_bounds(polygon, half)
        minx, minz, maxx, maxz = polygon.bounds
        step_limit = max_step if max_step is not None else 0.1 * np.hypot(maxx - minx,
                                                                         maxz - minz)
        self.weights: _Weights = (cohesion, separation, float(step_limit))
        angles = _GOLDEN_ANGLE * np.arange(len(half))
        self.fallback = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        self.inside = _inside(polygon)

    def random_start(self, rng: np.random.Generator, *, attempts: int = 8) -> np.ndarray:
        """Random centres inside the room, ``(n, 2)``; ``attempts`` redraws for centres
        that fall outside a non-rectangular room, then the rest go to a point inside it."""
        polygon, lo, hi = self.polygon, self.lo, self.hi
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

    def steer(self, positions: np.ndarray, iterations: int) -> np.ndarray:
        """``(n, 2)`` centres ``positions`` spread by ``iterations`` rounds of steering
        (the grammar's ``steeringIterations``); the input is not modified.

        Each round costs O(n²) for n items, all items moving at once; steering stops
        early at a fixed point (no item moves), which rounds after it would not change.
        Coincident items are pushed apart along a fixed, index-dependent direction, so
        the result is a pure function of the input.
        """
        p = np.array(positions, dtype=float).reshape(-1, 2)
        if len(p) < 2 or iterations <= 0 or not self.movable.any():
            return p
        if len(p) <= _FEW_ITEMS:
            return _rounds_few(p, self.radii, self.movable, self.inside, self.lo, self.hi,
                               self.fallback, iterations, self.weights)
        return _rounds_many(p, self.radii, self.movable, self.polygon, self.lo, self.hi,
                            self.fallback, iterations, self.weights)


_Weights = tuple[float, float, float]
"""``(cohesion, separation, step_limit)`` of :class:`Flock`."""


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


def _rounds_few(p: np.ndarray, radii: np.ndarray, movable: np.ndarray,
                inside: Callable[[_Steps], list[bool]], lo: np.ndarray, hi: np.ndarray,
                fallback: np.ndarray, iterations: int, weights: _Weights) -> np.ndarray:
    """:func:`_rounds_many` in Python floats, for a few items (a house's rooms steer two
    to four).

    Each of its few dozen array operations would cost more in numpy's call overhead than
    the arithmetic, so the same operations are done on floats, in the order numpy does
    them: sums over items run from the first item to the last (numpy reduces a
    non-contiguous axis sequentially), an item's own term is ``+0.0``, and square roots,
    maxima and minima are exact, so the positions are the same floats
    (``tests/unit/furniture/test_furniture_steering.py`` compares the two).

    What numpy works out but never uses is left out: the push between two items is
    worked out once per pair (the other item's is its negation, exactly, unless the two
    coincide and each takes its own fallback direction), pairs of items that both stay
    put are skipped, and so is the step of an item that stays put. ``inside`` tests which
    steps stay in the room (:func:`_inside`).
    """
    cohesion, separation, step_limit = weights
    n = len(p)
    xs, zs = p[:, 0].tolist(), p[:, 1].tolist()
    r, fall = radii.tolist(), fallback.tolist()
    movers = np.flatnonzero(movable).tolist()
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n) if movable[i] or movable[j]]
    (lox, loz), (hix, hiz) = lo.T.tolist(), hi.T.tolist()
    # per item, the term of each item: every round writes each term of a moving item's
    # row but its own, which stays +0.0
    push_x = [[0.0] * n for _ in range(n)]
    push_z = [[0.0] * n for _ in range(n)]
    for _ in range(iterations):
        sum_x, sum_z = reduce(add, xs), reduce(add, zs)
        for i, j in pairs:
            dx, dz = xs[i] - xs[j], zs[i] - zs[j]
            distance = math.sqrt(dx * dx + dz * dz)
            overlap = r[i] + r[j] - distance
            overlap = overlap if overlap >= 0.0 else 0.0
            if distance > 1e-9:
                term_x, term_z = dx / distance * overlap, dz / distance * overlap
                push_x[i][j], push_z[i][j] = term_x, term_z
                push_x[j][i], push_z[j][i] = -term_x, -term_z
            else:
                push_x[i][j], push_z[i][j] = fall[i][0] * overlap, fall[i][1] * overlap
                push_x[j][i], push_z[j][i] = fall[j][0] * overlap, fall[j][1] * overlap
        steps = []
        for i in movers:
            vx = (cohesion * ((sum_x - xs[i]) / (n - 1) - xs[i])
                  + separation * reduce(add, push_x[i]))
            vz = (cohesion * ((sum_z - zs[i]) / (n - 1) - zs[i])
                  + separation * reduce(add, push_z[i]))
            speed = math.sqrt(vx * vx + vz * vz)
            scale = step_limit / (speed if speed >= 1e-12 else 1e-12)
            scale = 1.0 if 1.0 <= scale else scale
            x, z = xs[i] + vx * scale, zs[i] + vz * scale
            x, z = (x if x >= lox[i] else lox[i]), (z if z >= loz[i] else loz[i])
            steps.append((i, x if x <= hix[i] else hix[i], z if z <= hiz[i] else hiz[i]))
        taken = [step for step, within in zip(steps, inside(steps)) if within]
        if not any(xs[i] != x or zs[i] != z for i, x, z in taken):
            break  # a fixed point: every further round would give the same positions
        for i, x, z in taken:
            xs[i], zs[i] = x, z
    return np.column_stack([xs, zs])


_Steps = list[tuple[int, float, float]]
"""``(item, x, z)`` of the steps of one round."""


def _inside(polygon: Polygon) -> Callable[[_Steps], list[bool]]:
    """A test of which steps end in the interior of ``polygon``: for a room that is the
    box of its bounds (most rooms), a comparison with them, which is what
    :func:`shapely.contains_xy` answers (a point on the boundary is not in the interior)
    without its cost per call."""
    minx, minz, maxx, maxz = polygon.bounds
    corners = {(minx, minz), (maxx, minz), (maxx, maxz), (minx, maxz)}
    ring = polygon.exterior.coords[:]
    # a ring through the four corners, each edge along a side, is the outline of the box
    if (not polygon.interiors and len(ring) == 5 and set(ring) == corners
            and all(a[0] == b[0] or a[1] == b[1] for a, b in zip(ring, ring[1:]))):
        return lambda steps: [minx < x < maxx and minz < z < maxz for _, x, z in steps]
    return lambda steps: shapely.contains_xy(polygon, [x for _, x, _ in steps],
                                             [z for _, _, z in steps]).tolist()
