"""Distance transforms of boolean grids (cga.checks._distance): the very numbers of
scipy.ndimage.distance_transform_edt, on random grids and on the scipy fallback; disc
dilations: the cells scipy's transform puts within reach; diamond dilations and
component labels: scipy.ndimage's binary dilation and labelling."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from cga.checks import _distance
from cga.checks._distance import (component_labels, diamond_dilation, disc_dilation,
                                  disc_dilations, distance_to_false, squared_distance_to_false,
                                  squared_reach)


def _grid(seed: int, rows: int, cols: int, density: float) -> np.ndarray:
    inside = np.random.default_rng(seed).random((rows, cols)) >= density
    inside[rows // 2, cols // 3] = False  # at least one false cell
    return inside


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 120), cols=st.integers(1, 120),
       density=st.sampled_from([0.0, 0.001, 0.02, 0.3, 0.9]))
def test_distances_are_scipys_bit_for_bit(seed, rows, cols, density):
    inside = _grid(seed, rows, cols, density)
    expected = ndimage.distance_transform_edt(inside)
    assert np.array_equal(distance_to_false(inside), expected)
    view = inside[::-1, ::2]  # a view, any layout
    if not view.all():
        assert np.array_equal(distance_to_false(view), ndimage.distance_transform_edt(view))
    squared = squared_distance_to_false(inside)
    assert np.array_equal(squared, np.rint(expected ** 2))


def test_large_grids_fall_back_on_scipy(monkeypatch):
    inside = _grid(7, 90, 70, 0.01)
    monkeypatch.setattr(_distance, "_EXACT_DIAGONAL_SQUARED", 100)
    assert np.array_equal(distance_to_false(inside), ndimage.distance_transform_edt(inside))


@pytest.mark.parametrize("resolution", [0.05, 0.1, 0.03, 0.07])
def test_squared_reach_picks_the_cells_the_float_test_picks(resolution):
    radius = 0.0
    for _ in range(80):
        radius += 0.05  # accumulated, as the local width's radii are
        reach = squared_reach(radius, resolution)
        d2 = np.arange(4 * reach + 8)
        within = np.sqrt(d2.astype(float)) * resolution <= radius
        assert np.array_equal(within, d2 <= reach)
    assert squared_reach(-1.0, 0.05) == -1
    assert squared_reach(0.0, 0.05) == 0


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 40), cols=st.integers(1, 40),
       density=st.sampled_from([0.002, 0.02, 0.3]), reach=st.integers(-1, 2000))
def test_disc_dilation_is_the_distance_transform_within_reach(seed, rows, cols, density,
                                                              reach):
    """disc_dilation marks exactly the cells whose squared distance (scipy's distance
    transform, squared and rounded) to a true cell is at most ``reach``, discs wider
    than the grid and empty masks included."""
    mask = np.random.default_rng(seed).random((rows, cols)) < density
    if mask.any():
        expected = np.rint(np.square(ndimage.distance_transform_edt(~mask))) <= reach
    else:
        expected = np.zeros_like(mask)
    assert np.array_equal(disc_dilation(mask, reach), expected)


def _within_reach(mask, reach):
    """The cells scipy's distance transform puts within ``reach`` (cells²) of ``mask``."""
    if not mask.any():
        return np.zeros_like(mask)
    return np.rint(np.square(ndimage.distance_transform_edt(~mask))) <= reach


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 40), cols=st.integers(1, 40),
       reaches=st.lists(st.integers(-1, 700), min_size=1, max_size=8),
       nested=st.booleans())
def test_disc_dilations_are_one_distance_transform_per_plane(seed, rows, cols, reaches,
                                                              nested):
    """Bit j of disc_dilations is the cells within reaches[j] of bit plane j, for discs
    of any sizes in any order, wider or taller than the grid, empty planes and negative
    reaches included; ``nested`` planes (each within the one before, as the local
    width's centres are) or independent ones. Bits past the reaches are ignored."""
    rng = np.random.default_rng(seed)
    if nested:
        clearance = rng.random((rows, cols))
        masks = [clearance >= (j + 1) / 10 for j in range(len(reaches))]
    else:
        masks = [rng.random((rows, cols)) < rng.choice([0.0, 0.01, 0.1, 0.5])
                 for _ in reaches]
    planes = rng.integers(0, 256, (rows, cols), dtype=np.uint8) >> len(reaches) << len(reaches)
    for j, mask in enumerate(masks):
        planes |= mask.astype(np.uint8) << j
    out = disc_dilations(planes, reaches)
    assert out.dtype == np.uint8 and out.shape == (rows, cols)
    for j, (mask, reach) in enumerate(zip(masks, reaches)):
        assert np.array_equal((out >> j) & 1 == 1, _within_reach(mask, reach))
    assert not (out >> len(reaches)).any()


def test_disc_dilations_take_eight_planes_at_most():
    with pytest.raises(ValueError):
        disc_dilations(np.zeros((2, 2), dtype=np.uint8), [1] * 9)


@settings(max_examples=60, deadline=None)
@given(radius=st.floats(0.0, 2.0), resolution=st.sampled_from([0.05, 0.04, 0.1, 0.037]))
def test_short_reach_splits_the_clearances_at_the_radius(radius, resolution):
    """The navigability check's drivable cells, read off a disc dilation, are the cells
    whose clearance (distance × resolution − half a cell, as the check computes it)
    reaches the robot radius: every squared distance up to the short reach falls short."""
    from cga.checks.navigability import _short_reach

    reach = _short_reach(radius, resolution)
    d2 = np.arange(0, 4 * (reach + 2) + 100)
    clearance = np.sqrt(d2.astype(np.float64)) * resolution - resolution / 2
    assert np.array_equal(clearance < radius, d2 <= reach)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 60), cols=st.integers(1, 60),
       density=st.sampled_from([0.0, 0.01, 0.1, 0.5, 0.97, 1.0]), steps=st.integers(1, 9))
def test_diamond_dilation_is_scipys_binary_dilation(seed, rows, cols, density, steps):
    mask = np.random.default_rng(seed).random((rows, cols)) >= density
    assert np.array_equal(diamond_dilation(mask, steps),
                          ndimage.binary_dilation(mask, iterations=steps))


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 60), cols=st.integers(1, 60),
       density=st.sampled_from([0.0, 0.2, 0.4, 0.45, 0.6, 1.0]))
def test_component_labels_are_scipys_pieces(seed, rows, cols, density):
    """Same pieces as ndimage.label: two cells share a label in one exactly when they
    share one in the other, and false cells are 0 in both."""
    mask = np.random.default_rng(seed).random((rows, cols)) >= density
    ours = component_labels(mask)
    theirs, count = ndimage.label(mask)
    assert np.array_equal(ours == 0, theirs == 0)
    pairs = np.unique(np.column_stack([ours[mask], theirs[mask]]), axis=0)
    assert len(pairs) == count == len(np.unique(ours[mask]))
