"""Random streams keyed by the build seed and a name, so builds are reproducible and local.

Each shape draws from its own stream derived from (seed, its path in the shape tree),
so editing one rule re-rolls only the shapes under it (docs/language.md, "Stochastic
choice"). A stream is a
:class:`numpy.random.Generator` seeded by a :class:`numpy.random.SeedSequence` over the
build seed and a stable digest of the key. The digest is BLAKE2b (never Python's
:func:`hash`, which is salted per process), so the same seed gives the same numbers in
every process, on every machine.

Variables' ``[a;b]`` ranges are drawn once per build from the stream keyed by
``("variables", name)``: renaming or adding another variable does not change a value.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence

import numpy as np

__all__ = ["key_digest", "stream", "shape_rng", "variable_rng"]

_SEPARATOR = b"\x1f"  # ASCII unit separator: cannot occur in a symbol name


def key_digest(key: Sequence[str]) -> int:
    """A stable 128-bit integer digest of a key (a sequence of names), via BLAKE2b.

    The parts are joined with a separator that cannot occur in names, so
    ``("ab", "c")`` and ``("a", "bc")`` differ.
    """
    data = _SEPARATOR.join(part.encode("utf-8") for part in key)
    return int.from_bytes(hashlib.blake2b(data, digest_size=16).digest(), "little")


def stream(seed: int, key: Sequence[str]) -> np.random.Generator:
    """The random stream of ``key`` in the build with ``seed``.

    Parameters
    ----------
    seed:
        The build seed, a non-negative integer.
    key:
        Names identifying the stream, e.g. a shape path ``("Lot", "Body", "Floor[1]")``.

    Raises
    ------
    ValueError
        ``seed`` is negative (SeedSequence entropy must be non-negative).
    """
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed}")
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(seed), key_digest(key)])))


def shape_rng(seed: int, path: Sequence[str] | str) -> np.random.Generator:
    """The stream of the shape at ``path`` (a tuple of path elements or ``"A/B/C[2]"``)."""
    parts = tuple(path.split("/")) if isinstance(path, str) else tuple(path)
    return stream(seed, ("shape",) + parts)


def variable_rng(seed: int, name: str) -> np.random.Generator:
    """The stream that draws variable ``name``'s ``[a;b]`` range, once per build."""
    return stream(seed, ("variables", name))
