"""The exploration proxy's parts (cga.difficulty.exploration) against straightforward
references: the coarse grids against numpy's block reductions, the frontier's 3 × 3
squares against the disc dilation, the sensor against the ray cast over every half-cell
step on the bare grid, the limited goal search against a full Dijkstra search. All
exact."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import dijkstra

from cga.checks._distance import disc_dilation
from cga.difficulty.exploration import (_coarsen, _grid_graph, _nearest, _ray_offsets, _round,
                                        _Sensor)


def _coarsen_by_blocks(mask, factor, how):
    rows, cols = (-(-n // factor) * factor for n in mask.shape)
    padded = np.zeros((rows, cols), dtype=bool)
    padded[:mask.shape[0], :mask.shape[1]] = mask
    blocks = padded.reshape(rows // factor, factor, cols // factor, factor)
    return blocks.any(axis=(1, 3)) if how == "any" else blocks.all(axis=(1, 3))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 40), cols=st.integers(1, 40),
       factor=st.integers(1, 6), density=st.sampled_from([0.05, 0.5, 0.95]),
       how=st.sampled_from(["any", "all"]))
def test_coarsen_is_the_block_reduction(seed, rows, cols, factor, density, how):
    mask = np.random.default_rng(seed).random((rows, cols)) < density
    assert np.array_equal(_coarsen(mask, factor, how), _coarsen_by_blocks(mask, factor, how))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 30), cols=st.integers(1, 30),
       density=st.sampled_from([0.0, 0.05, 0.3, 0.9]))
def test_round_is_the_disc_dilation_by_two(seed, rows, cols, density):
    mask = np.random.default_rng(seed).random((rows, cols)) < density
    assert np.array_equal(_round(mask), disc_dilation(mask, 2))


def _seen_by_every_step(occluder, at, reach):
    """The sensor as first written: every half-cell step of every ray, bounds tested."""
    offsets = _ray_offsets(reach)
    rows, cols = occluder.shape
    seen = np.zeros_like(occluder)
    r = at[0] + offsets[..., 0]
    c = at[1] + offsets[..., 1]
    inside = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
    r, c = np.where(inside, r, 0), np.where(inside, c, 0)
    stop = (occluder[r, c] & ((r != at[0]) | (c != at[1]))) | ~inside
    visible = np.cumsum(stop, axis=1) == 0
    seen[r[visible], c[visible]] = True
    seen[at] = True
    return seen


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 50), cols=st.integers(1, 50),
       density=st.sampled_from([0.0, 0.03, 0.2, 0.6]), reach=st.integers(0, 25),
       looks=st.integers(1, 3))
def test_sensor_sees_what_every_ray_step_sees(seed, rows, cols, density, reach, looks):
    """The sensor (each ray's cells once, in a frame of occluders) marks the very cells
    of the ray cast over every step, from several places in turn, the robot's own cell
    an occluder or not."""
    rng = np.random.default_rng(seed)
    occluder = rng.random((rows, cols)) < density
    sensor = _Sensor(occluder, reach)
    expected = np.zeros_like(occluder)
    for _ in range(looks):
        at = (int(rng.integers(rows)), int(rng.integers(cols)))
        sensor.sense(at)
        expected |= _seen_by_every_step(occluder, at, reach)
        assert np.array_equal(sensor.seen, expected)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 30), cols=st.integers(1, 30),
       share=st.sampled_from([0.01, 0.1, 0.5]), near=st.sampled_from([0.0, 0.3, 1.0, 3.0]))
def test_nearest_goal_is_the_full_searchs(seed, rows, cols, share, near):
    """The goal search stopped at ``near`` finds the goal and the very distance (bit for
    bit) of a full search, ties broken alike; None when no candidate is reachable."""
    rng = np.random.default_rng(seed)
    drivable = rng.random((rows, cols)) < 0.7
    drivable[0, 0] = True
    graph, index = _grid_graph(drivable, 0.25)
    candidates = index[drivable & (rng.random((rows, cols)) < share)]
    full = dijkstra(graph, directed=True, indices=0)
    reachable = candidates[np.isfinite(full[candidates])]
    expected = None
    if reachable.size:
        goal = int(reachable[np.argmin(full[reachable])])
        expected = (goal, float(full[goal]))
    assert _nearest(graph, 0, candidates, near) == expected
