"""Random start positions and separation steering."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings, strategies as st
from shapely.geometry import Polygon, box

from cga.operations.furniture.steering import (_GOLDEN_ANGLE, Flock, _centre_bounds, _inside,
                                               _rounds_few, _rounds_many)

L_ROOM = Polygon([(0, 0), (6, 0), (6, 2), (2, 2), (2, 5), (0, 5)])


def random_start(polygon, half, rng):
    return Flock(polygon, half, np.ones(len(half)), np.ones(len(half), bool)).random_start(rng)


def separation_steering(positions, radii, movable, polygon, half, iterations):
    return Flock(polygon, half, radii, movable).steer(positions, iterations)


def overlap(points: np.ndarray, radii: np.ndarray) -> float:
    total = 0.0
    for i in range(len(points)):
        for j in range(i + 1, len(points)):
            total += max(0.0, radii[i] + radii[j] - np.linalg.norm(points[i] - points[j]))
    return total


def test_random_start_is_inside_and_reproducible():
    half = np.full((40, 2), 0.3)
    first = random_start(L_ROOM, half, np.random.default_rng(3))
    again = random_start(L_ROOM, half, np.random.default_rng(3))
    assert np.array_equal(first, again)
    assert shapely.contains_xy(L_ROOM, first[:, 0], first[:, 1]).all()


def test_an_item_larger_than_the_room_starts_in_the_middle():
    points = random_start(box(0, 0, 2, 2), np.array([[3.0, 0.5]]), np.random.default_rng(0))
    assert points[0, 0] == 1.0


def test_separation_spreads_items_apart_and_keeps_them_inside():
    room = box(0, 0, 6, 5)
    rng = np.random.default_rng(11)
    start = 3 + rng.normal(0, 0.05, size=(6, 2))
    radii = np.full(6, 0.6)
    half = np.full((6, 2), 0.4)
    movable = np.ones(6, dtype=bool)
    result = separation_steering(start, radii, movable, room, half, 30)
    assert overlap(result, radii) < 0.2 * overlap(start, radii)
    assert (result >= half).all() and (result[:, 0] <= 6 - 0.4).all() and (result[:, 1] <= 5 - 0.4).all()
    assert np.allclose(start, 3 + np.random.default_rng(11).normal(0, 0.05, size=(6, 2)))


def test_fixed_items_do_not_move_and_zero_iterations_change_nothing():
    room = box(0, 0, 6, 5)
    start = np.array([[3.0, 2.5], [3.1, 2.5], [3.0, 2.6]])
    movable = np.array([False, True, True])
    result = separation_steering(start, np.full(3, 0.5), movable, room, np.full((3, 2), 0.3), 10)
    assert np.array_equal(result[0], start[0]) and not np.allclose(result[1:], start[1:])
    assert np.array_equal(separation_steering(start, np.full(3, 0.5), movable, room,
                                              np.full((3, 2), 0.3), 0), start)


def test_coincident_items_separate_deterministically():
    room = box(0, 0, 6, 5)
    start = np.full((3, 2), 2.5)
    args = (np.full(3, 0.5), np.ones(3, dtype=bool), room, np.full((3, 2), 0.3), 20)
    first = separation_steering(start, *args)
    assert np.array_equal(first, separation_steering(start, *args))
    assert overlap(first, np.full(3, 0.5)) < overlap(start, np.full(3, 0.5))


def test_steps_never_leave_a_non_rectangular_room():
    rng = np.random.default_rng(5)
    half = np.full((8, 2), 0.2)
    start = random_start(L_ROOM, half, rng)
    result = separation_steering(start, np.full(8, 1.0), np.ones(8, dtype=bool), L_ROOM, half, 40)
    assert shapely.contains_xy(L_ROOM, result[:, 0], result[:, 1]).all()


def test_steering_stops_at_a_fixed_point_with_the_same_result():
    room = box(0, 0, 6, 5)
    start = np.array([[1.0, 1.0], [5.0, 4.0]])  # cohesion and separation settle to a fixed point
    half = np.full((2, 2), 0.9)
    few = separation_steering(start, np.full(2, 0.5), np.ones(2, bool), room, half, 300)
    many = separation_steering(start, np.full(2, 0.5), np.ones(2, bool), room, half, 10**12)
    assert np.array_equal(few, many)


def plain_steering(positions, radii, movable, polygon, half, iterations):
    """Reynolds' two behaviours written plainly (numpy.linalg.norm, numpy.clip, every
    round in full): the reference the round-trimmed implementation must match bit for bit."""
    p = np.array(positions, dtype=float)
    n = len(p)
    if n < 2 or iterations <= 0 or not movable.any():
        return p
    minx, minz, maxx, maxz = polygon.bounds
    lo, hi = np.array([minx, minz]) + half, np.array([maxx, maxz]) - half
    middle = np.array([(minx + maxx) / 2, (minz + maxz) / 2])
    lo, hi = np.where(lo <= hi, lo, middle), np.where(lo <= hi, hi, middle)
    step_limit = 0.1 * np.hypot(maxx - minx, maxz - minz)
    angles = np.pi * (3 - np.sqrt(5)) * np.arange(n)
    fallback = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    for _ in range(iterations):
        delta = p[:, None, :] - p[None, :, :]
        distance = np.linalg.norm(delta, axis=2)
        np.fill_diagonal(distance, np.inf)
        direction = np.where(distance[..., None] > 1e-9,
                             delta / np.where(distance > 1e-9, distance, 1.0)[..., None],
                             fallback[:, None, :])
        overlap = np.clip(radii[:, None] + radii[None, :] - distance, 0.0, None)
        np.fill_diagonal(overlap, 0.0)
        push = (direction * overlap[..., None]).sum(axis=1)
        pull = (p.sum(axis=0) - p) / (n - 1) - p
        velocity = 0.05 * pull + 0.5 * push
        speed = np.linalg.norm(velocity, axis=1, keepdims=True)
        velocity *= np.minimum(1.0, step_limit / np.maximum(speed, 1e-12))
        proposal = np.clip(p + velocity, lo, hi)
        take = movable & shapely.contains_xy(polygon, proposal[:, 0], proposal[:, 1])
        p[take] = proposal[take]
    return p


def test_steering_gives_the_same_floats_as_the_plain_formulation():
    rng = np.random.default_rng(5)
    rooms = [box(0, 0, 5, 4), L_ROOM, box(0, 0, 1.5, 1.5)]
    for case in range(300):
        room = rooms[case % 3]
        n = int(rng.integers(1, 14))
        half = rng.uniform(0.1, 1.2, (n, 2))
        start = random_start(room, half, rng)
        if case % 5 == 0 and n > 2:
            start[2] = start[1]  # coincident items take the fallback direction
        radii = np.hypot(half[:, 0], half[:, 1])
        movable = rng.random(n) > 0.2
        iterations = int(rng.integers(0, 15))
        got = separation_steering(start, radii, movable, room, half, iterations)
        want = plain_steering(start, radii, movable, room, half, iterations)
        assert got.tobytes() == want.tobytes(), case


@settings(max_examples=300, deadline=None)
@given(n=st.integers(2, 8), seed=st.integers(0, 2**32 - 1), iterations=st.integers(1, 12),
       room=st.sampled_from([box(0, 0, 6, 5), box(0, 0, 1.5, 1.2), L_ROOM]),
       coincident=st.booleans())
def test_few_items_give_the_floats_numpy_gives(n, seed, iterations, room, coincident):
    """The small-room rounds (Python floats) against the array rounds, bit for bit."""
    rng = np.random.default_rng(seed)
    half = rng.uniform(0.05, 0.8, size=(n, 2))
    start = random_start(room, half, rng)
    if coincident:
        start[1:3] = start[0]
    radii = rng.uniform(0.1, 1.5, size=n)
    movable = rng.random(n) < 0.8
    movable[0] = True
    lo, hi = _centre_bounds(room, half)
    angles = _GOLDEN_ANGLE * np.arange(n)
    fallback = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    weights = (0.05, 0.5, float(rng.uniform(0.05, 1.0)))
    args = (lo, hi, fallback, iterations, weights)
    few = _rounds_few(start.copy(), radii, movable, _inside(room), *args)
    many = _rounds_many(start.copy(), radii, movable, room, *args)
    assert few.tobytes() == many.tobytes()


@settings(max_examples=200, deadline=None)
@given(room=st.sampled_from([box(0, 0, 6, 5), box(-1.3, 0.7, 0.1, 2.9), L_ROOM,
                             Polygon([(0, 0), (6, 0), (6, 5), (0, 5), (0, 2)]),
                             box(0, 0, 6, 5).difference(box(2, 2, 3, 3))]),
       picks=st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4),
                                st.floats(-2, 7), st.floats(-2, 7)), min_size=1, max_size=12))
def test_the_inside_test_answers_as_contains_xy(room, picks):
    """Points on the outline, at the corners and anywhere else: the bounds comparison of a
    box room gives what shapely gives, as does the test of any other room."""
    minx, minz, maxx, maxz = room.bounds
    xs, zs = (minx, (minx + maxx) / 2, maxx), (minz, (minz + maxz) / 2, maxz)
    steps = [(k, xs[a] if a < 3 else x, zs[b] if b < 3 else z)
             for k, (a, b, x, z) in enumerate(picks)]
    want = shapely.contains_xy(room, [x for _, x, _ in steps], [z for _, _, z in steps])
    assert _inside(room)(steps) == want.tolist()


def plain_start(polygon, half, rng, attempts=8):
    """Random starts written plainly, each draw's bounds made afresh: the reference for
    the starts of a :class:`Flock`, whose bounds are made once per room."""
    minx, minz, maxx, maxz = polygon.bounds
    lo, hi = np.array([minx, minz]) + half, np.array([maxx, maxz]) - half
    middle = np.array([(minx + maxx) / 2, (minz + maxz) / 2])
    lo, hi = np.where(lo <= hi, lo, middle), np.where(lo <= hi, hi, middle)
    points = rng.uniform(lo, hi)
    for _ in range(attempts):
        outside = ~shapely.contains_xy(polygon, points[:, 0], points[:, 1])
        points[outside] = rng.uniform(lo[outside], hi[outside])
    outside = ~shapely.contains_xy(polygon, points[:, 0], points[:, 1])
    points[outside] = polygon.representative_point().coords[0]
    return points


@settings(max_examples=100, deadline=None)
@given(n=st.integers(1, 10), seed=st.integers(0, 2**32 - 1),
       room=st.sampled_from([box(0, 0, 6, 5), box(0, 0, 1.5, 1.2), L_ROOM]))
def test_a_flock_starts_where_the_plain_formulation_starts(n, seed, room):
    """Three attempts of one flock against draws made afresh, from one stream each."""
    half = np.random.default_rng(seed).uniform(0.05, 1.0, size=(n, 2))
    flock = Flock(room, half, np.ones(n), np.ones(n, bool))
    ours, plain = np.random.default_rng(seed), np.random.default_rng(seed)
    for _ in range(3):
        assert flock.random_start(ours).tobytes() == plain_start(room, half, plain).tobytes()
