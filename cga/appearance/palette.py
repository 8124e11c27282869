"""Which material dresses which surface in a build: neutral, or drawn with the seed.

A :class:`Palette` answers "what is this room's wall paint, this chair's wood?" once per
key and remembers the answer, so a surface class shares one look where it should:

* per build: facade, ceiling, slab edges, roof, stair, rail, massing shapes;
* per room: wall paint and floor (the room type restricts the rows: tiles in wet
  rooms, carpet in bedrooms and offices);
* per room and model: each part class of a furniture model (the chairs of a room share
  one wood), and separately a part that a row targets by name (MSU material targets).

Neutral (``mode="neutral"``) takes each class' first allowed row, and furniture parts
keep their model's own colours. Random (``mode="random"``) draws a row by ``Weight``
among the allowed rows with a weight, then varies it (:meth:`MaterialRow.look`), from
the stream ``("appearance", *key)`` of the build seed (:mod:`cga.randomness`): the same
seed gives the same materials, and a key's draw does not depend on the order surfaces
are asked for.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from cga.randomness import stream

from .library import FALLBACK_PART, MaterialLibrary, MaterialRow, part_class
from .material import RGB, Material

__all__ = ["MaterialMode", "MATERIAL_MODES", "Palette"]

MaterialMode = Literal["neutral", "random"]
MATERIAL_MODES: tuple[str, ...] = ("neutral", "random")
"""Values of ``--materials`` and the grammar variable ``materials``."""


class Palette:
    """The materials of one build (see the module notes)."""

    def __init__(self, library: MaterialLibrary, seed: int, mode: MaterialMode = "neutral"):
        if mode not in MATERIAL_MODES:
            raise ValueError(f"materials must be one of {', '.join(MATERIAL_MODES)}, got {mode!r}")
        self.library = library
        self.seed = seed
        self.mode = mode
        self._chosen: dict[tuple[str, ...], Material] = {}
        self._parts: dict[tuple[str, str], tuple[str, bool]] = {}
        self._part_lists: dict[tuple[str, ...], list[Material]] = {}

    def surface(self, surface: str, *, room_type: str | None = None,
                key: tuple[str, ...] = ()) -> Material:
        """The material of a structure surface (``wall``, ``floor``, ...) of a room of
        ``room_type``, drawn once per ``(surface, *key)``."""
        full = (surface, *key)
        if full not in self._chosen:
            rows = self.library.candidates(surface, room=room_type)
            self._chosen[full] = self._pick(rows, full, None)
        return self._chosen[full]

    def part(self, model: str, part: str, color: RGB, *, key: tuple[str, ...] = ()) -> Material:
        """The material of furniture ``model``'s part (OBJ group) ``part``, whose own
        colour is ``color``; drawn once per ``(model, part class, key)``, or per part
        when a row targets the part by name."""
        known = self._parts.get((model, part))
        if known is None:
            known = self._parts[(model, part)] = (self._part_surface(part),
                                                  self.library.targets(model, part))
        surface, targeted = known
        full = ("part", model, surface, *key, *((part.lower(),) if targeted else ()))
        if self.mode == "neutral":
            full = (*full, repr(color))
        if full not in self._chosen:
            rows = self.library.candidates(surface, model=model, part=part)
            self._chosen[full] = self._pick(rows, full, color)
        return self._chosen[full]

    def parts(self, model: str, parts: Sequence[tuple[str, RGB]], *,
              key: tuple[str, ...] = ()) -> list[Material]:
        """:meth:`part` of each ``(part, colour)`` of ``model`` (a model's part list, the
        same for every item of it: asked once per model and key, as the chairs of a
        room share one answer).

        A neutral look depends on neither the key nor the seed (the first allowed row
        in the part's own colour), so the neutral answer for a model and its parts is
        worked out once per material table and shared by every build (a house has a few
        dozen models but hundreds of (model, room) pairs)."""
        if self.mode == "neutral":
            return list(self.library.remember(("neutral parts", model, *parts),
                                              lambda: self._part_list(model, parts, key)))
        full = ("parts", model, *key)
        if full not in self._part_lists:
            self._part_lists[full] = self._part_list(model, parts, key)
        return list(self._part_lists[full])

    def _part_list(self, model: str, parts: Sequence[tuple[str, RGB]],
                   key: tuple[str, ...]) -> list[Material]:
        return [self.part(model, name, color, key=key) for name, color in parts]

    def _part_surface(self, part: str) -> str:
        surface = part_class(part, self.library.part_classes)
        return surface if self.library.candidates(surface) else FALLBACK_PART

    def _pick(self, rows: list[MaterialRow], key: tuple[str, ...], color: RGB | None) -> Material:
        if not rows:  # the table guarantees an unrestricted row per class
            raise AssertionError(f"no material row for {key}")
        if self.mode == "neutral":
            return rows[0].look(None, color)
        weighted = [r for r in rows if r.weight > 0] or rows[:1]
        rng = stream(self.seed, ("appearance", *key))
        weights = np.array([r.weight for r in weighted], dtype=float)
        total = weights.sum()
        index = int(rng.choice(len(weighted), p=weights / total)) if total > 0 else 0
        return weighted[index].look(rng)
