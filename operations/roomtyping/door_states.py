"""Door states: how a build leaves each door leaf (closed, open or ajar; docs/outputs.md).

A robot world needs doors a planner must open as well as doors it can drive through.
``type_rooms(..., door_state=...)`` sets every door of a floor to one state, or draws one
per door from the floor's random stream (``"random"``), so the same seed gives the same
doors. An ajar leaf stands between :data:`AJAR_RANGE` when drawn, at :data:`AJAR_ANGLE`
when asked for; an open leaf at :data:`~cga.model.DOOR_OPEN_ANGLE`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from cga.model import DOOR_OPEN_ANGLE, DOOR_STATES, Door

__all__ = ["AJAR_ANGLE", "AJAR_RANGE", "DOOR_STATE_CHOICES", "with_door_states"]

AJAR_ANGLE = math.radians(30.0)
"""rad: the angle of a leaf built ``"ajar"``."""

AJAR_RANGE = (math.radians(15.0), math.radians(45.0))
"""rad: the angles a randomly ajar leaf is drawn from (uniform)."""

DOOR_STATE_CHOICES = (*DOOR_STATES, "random")
"""Values of ``type_rooms``' ``door_state``."""


def with_door_states(doors: Sequence[Door], state: str, rng: np.random.Generator) -> list[Door]:
    """``doors`` with their ``state`` and ``angle`` set.

    Parameters
    ----------
    doors:
        The floor's doors, in id order.
    state:
        One of :data:`DOOR_STATE_CHOICES`; ``"random"`` draws a state per door (each
        equally likely) and an angle for ajar ones.
    rng:
        The floor's random stream; only ``"random"`` draws from it, so a build with a
        fixed state keeps every other random choice of the floor.

    Raises
    ------
    ValueError
        ``state`` is not one of :data:`DOOR_STATE_CHOICES`.

    Examples
    --------
    >>> from cga.model import Door
    >>> door = Door(0, 3, (0, 1), (1.0, 0.0), 0.9, 2.1, swing_room=1)
    >>> [(d.state, round(d.angle, 4)) for d in with_door_states([door], "open", None)]
    [('open', 1.5708)]
    """
    if state not in DOOR_STATE_CHOICES:
        raise ValueError(f"door_state must be one of {DOOR_STATE_CHOICES}, got {state!r}")
    out = []
    for door in doors:
        angle = None
        if state == "random":
            chosen = DOOR_STATES[int(rng.integers(len(DOOR_STATES)))]
        else:
            chosen = next(s for s in DOOR_STATES if s == state)  # checked above
            if chosen == "ajar":
                angle = float(rng.uniform(*AJAR_RANGE))
        if angle is None:
            angle = {"closed": 0.0, "open": DOOR_OPEN_ANGLE, "ajar": AJAR_ANGLE}[chosen]
        out.append(replace(door, state=chosen, angle=angle))
    return out
