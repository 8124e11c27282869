"""Furniture variation: each item's own size, drawn within its row's ``sizeJitter``.

The TFG office generator varies the dimensions of its models between builds (Table
3.2.A: a desk's length and width, a shelf's height, a chair's width, ...) within ranges
that keep a model's proportions. Here a furniture table sets the range per row
(``sizeJitter``: a fraction of each extent, docs/furniture.md) and every placed item
gets its own size, drawn uniformly in ``[1 - f, 1 + f]`` × the model's extent per axis.

The solver places the item at that size, and the meshing layer scales the model's
visual mesh and its convex collision parts by the same matrix
(:func:`cga.meshing.items.item_transform`), so the layout, the physics and every export
see the one real size. Uniform rather than Gaussian (the TFG uses both): the range is a
hard bound a table author can rely on.
"""

from __future__ import annotations

import numpy as np

__all__ = ["jittered_size"]


def jittered_size(size: tuple[float, float, float], jitter: tuple[float, float, float],
                  rng: np.random.Generator) -> tuple[float, float, float]:
    """``size`` with each extent scaled by a uniform factor in ``[1 - j, 1 + j]``.

    Parameters
    ----------
    size:
        The model's (width, height, depth) in metres.
    jitter:
        The fraction per extent, each in [0, 0.5] (:data:`.rules.MAX_SIZE_JITTER`).
    rng:
        The stream to draw from; nothing is drawn when every fraction is 0, so a table
        without jitter leaves the stream untouched.

    Returns
    -------
    tuple of float
        The item's size.

    Examples
    --------
    >>> import numpy as np
    >>> jittered_size((1.0, 0.75, 0.6), (0.0, 0.0, 0.0), np.random.default_rng(1))
    (1.0, 0.75, 0.6)
    >>> w, h, d = jittered_size((1.0, 0.75, 0.6), (0.1, 0.0, 0.1), np.random.default_rng(1))
    >>> 0.9 <= w <= 1.1 and h == 0.75 and 0.54 <= d <= 0.66
    True
    """
    if not any(jitter):
        return size
    factors = 1.0 + np.asarray(jitter) * rng.uniform(-1.0, 1.0, size=3)
    w, h, d = (float(s * f) for s, f in zip(size, factors))
    return (w, h, d)
