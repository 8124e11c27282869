"""Random streams: reproducible across processes, independent per path and per variable."""

import subprocess
import sys

import numpy as np
import pytest

from cga.randomness import key_digest, shape_rng, variable_rng


def test_same_seed_and_path_same_numbers():
    a = shape_rng(7, ("Lot", "Body", "Floor[1]")).random(5)
    b = shape_rng(7, "Lot/Body/Floor[1]").random(5)
    assert np.array_equal(a, b)


def test_different_paths_seeds_and_streams_differ():
    base = shape_rng(7, ("Lot", "Body")).random(3)
    assert not np.array_equal(base, shape_rng(8, ("Lot", "Body")).random(3))
    assert not np.array_equal(base, shape_rng(7, ("Lot", "Body[0]")).random(3))
    assert not np.array_equal(base, variable_rng(7, "Body").random(3))


def test_digest_separates_parts():
    assert key_digest(("ab", "c")) != key_digest(("a", "bc"))


def test_stable_across_processes():
    """Python's hash() is salted per process; the streams must not be."""
    code = ("from cga.randomness import shape_rng;"
            "print(repr(shape_rng(3, ('Lot', 'A[2]')).random()))")
    runs = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           check=True, env={"PYTHONHASHSEED": str(i)}).stdout for i in (1, 2)}
    assert len(runs) == 1
    assert float(runs.pop()) == shape_rng(3, ("Lot", "A[2]")).random()


def test_negative_seed_rejected():
    with pytest.raises(ValueError, match="non-negative"):
        shape_rng(-1, ("Lot",))
