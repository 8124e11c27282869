"""The partition code's own error (docs/architecture.md, "Errors").

The DCEL, the BSP partition and the plan assembly raise :class:`PartitionError` when
the geometry they are given cannot be made into rooms (a degenerate footprint, a cut
that is not a chord, a room with no floor inside its walls). Callers that turn those
into user errors (``make_floor``, ``plan_from_rectangles``) catch only this type, so a
``ValueError`` from a bug in shapely, numpy or this package surfaces as a bug.
"""

from __future__ import annotations

__all__ = ["PartitionError"]


class PartitionError(ValueError):
    """Geometry the floor partition cannot cut into rooms; the message says what."""
