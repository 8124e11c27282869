"""Disorder: movable items (chairs) pushed and turned a little off their tidy pose.

Real rooms are never arranged perfectly: chairs stand pulled back and askew. The TFG
office generator has a noise parameter in [0, 1] per build or room that scales "the
rotation and displacement" of the chairs (§3.4, fig. 4.2.E); its robot runs used 0.4.
Here ``disorder`` d scales, for every movable item (``isMovable``, by default the
chairs; :meth:`.rules.FurnitureRule.movable`):

* a turn by a free angle drawn uniformly in ``[-d, d]`` × :data:`MAX_YAW`;
* a shift drawn uniformly in the disc of radius d × :data:`MAX_SHIFT`; for a child
  (a chair at its table or desk) in the half of it away from its parent, as chairs get
  pulled out, not pushed in.

The disturbed pose must keep every guarantee of a tidy one (docs/furniture.md): it is
tested by the room's :class:`~.layout.Layout` with the item's body and clearance boxes
turned (walls, other items, their clearances, door swings, windows, the passage rule),
and against its parent: the pair distances still hold, a ``canBeAround`` child still
looks at its parent (its front ray meets the parent's footprint), a child in front of
its parent stays in front of it, within its width. A rejected sample is drawn again, up
to :data:`SAMPLES` times, then at half and a quarter of the noise; when nothing fits the
item keeps its tidy pose. An item with children of its own stays put (they were placed
relative to it), and so does a non-colliding one.

A table row may set its own ``disorder`` (the TFG gives one value per room): its items
take that instead of the build's.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from shapely.geometry import LineString

from cga.model import front_vector

from .layout import ItemSpec, Layout, Pose, body_polygon

__all__ = ["MAX_YAW", "MAX_SHIFT", "SAMPLES", "disturb"]

MAX_YAW = math.radians(30.0)
"""Largest free turn (radians) of a movable item at disorder 1."""

MAX_SHIFT = 0.2
"""Largest shift (m) of a movable item at disorder 1."""

SAMPLES = 8
"""Poses drawn per noise scale before the noise is halved."""

_SCALES = (1.0, 0.5, 0.25)
_TOLERANCE = 1e-6
_RAY = 100.0


def _keeps_pair(spec: ItemSpec, pose: Pose, parent: ItemSpec, parent_pose: Pose) -> bool:
    """Whether ``spec`` at ``pose`` still stands to its parent as its rule says."""
    rule = spec.rule
    body, parent_body = body_polygon(spec, pose), body_polygon(parent, parent_pose)
    gap = parent_body.distance(body)
    if gap < rule.min_pair_distance - _TOLERANCE:
        return False
    if rule.max_gap is not None and not rule.is_along_wall and gap > rule.max_gap + _TOLERANCE:
        return False
    front = np.array(front_vector(pose.rotation, pose.yaw))
    if rule.can_be_around:
        ray = LineString([(pose.x, pose.z), (pose.x + front[0] * _RAY, pose.z + front[1] * _RAY)])
        return bool(ray.intersects(parent_body))
    parent_front = np.array(front_vector(parent_pose.rotation, parent_pose.yaw))
    to_parent = np.array([parent_pose.x - pose.x, parent_pose.z - pose.z])
    lateral = abs(float(np.dot(to_parent, (-parent_front[1], parent_front[0]))))
    if rule.is_on_the_side:
        return lateral >= (parent.width + spec.width) / 2 - _TOLERANCE
    ahead = -float(np.dot(to_parent, parent_front))
    return ahead > 0 and lateral <= parent.width / 2 + _TOLERANCE


def disturb(layout: Layout, specs: Sequence[ItemSpec], movable: set[str],
            related: Mapping[str, frozenset[str]], rng: np.random.Generator,
            disorder: float) -> int:
    """Turn and shift the movable items of a finished room layout, in place.

    Parameters
    ----------
    layout:
        The room's layout with every item placed; disturbed items are moved in it.
    specs:
        The room's items in placement order (the order they are disturbed in).
    movable:
        Names of the items disorder may move.
    related:
        Item name → its parent and children (see :meth:`.layout.Layout.conflicts`).
    rng:
        The room's random stream.
    disorder:
        The noise scale in [0, 1]; a row's own ``disorder`` replaces it for its items.
        Items at 0 stay as they are and draw nothing.

    Returns
    -------
    int
        How many items moved.

    Notes
    -----
    At most ``3 × SAMPLES`` conflict tests per movable item, each the cost of one
    placement test.
    """
    moved = 0
    for spec in specs:
        entry = layout.placed.get(spec.name)
        noise = disorder if spec.rule.disorder is None else spec.rule.disorder
        if entry is None or noise <= 0 or spec.name not in movable or spec.rule.non_collision:
            continue
        if any(c in layout.placed for c in related.get(spec.name, frozenset())
               if c != spec.rule.pair_with):
            continue
        parent = layout.placed.get(spec.rule.pair_with) if spec.rule.pair_with else None
        tidy = entry[1]
        # a child is pulled away from its parent (a chair from its table), anything else
        # shifts any way
        back = np.negative(front_vector(tidy.rotation))
        away, spread = ((math.atan2(back[1], back[0]), math.pi / 2) if parent is not None
                        else (0.0, math.pi))
        layout.remove(spec.name)
        chosen = None
        for scale in _SCALES:
            for _ in range(SAMPLES):
                yaw = noise * scale * MAX_YAW * float(rng.uniform(-1.0, 1.0))
                radius = noise * scale * MAX_SHIFT * math.sqrt(float(rng.random()))
                angle = away + float(rng.uniform(-spread, spread))
                pose = Pose(tidy.x + radius * math.cos(angle), tidy.z + radius * math.sin(angle),
                            tidy.rotation, yaw)
                if parent is not None and not _keeps_pair(spec, pose, *parent):
                    continue
                if layout.fits(spec, pose, related.get(spec.name, frozenset())):
                    chosen = pose
                    break
            if chosen is not None:
                break
        layout.add(spec, chosen if chosen is not None else tidy)
        moved += chosen is not None
    return moved
