"""A resolved PBR material: what every exporter writes for a surface (docs/appearance.md).

glTF 2.0's metallic-roughness model (Khronos, *glTF 2.0 specification*, §3.9): a base
colour, a roughness and a metalness, and an alpha for see-through surfaces (window
glass). Colours are kept in sRGB, as people pick them and as the material table writes
them; :meth:`Material.linear_rgba` gives the linear values glTF's ``baseColorFactor``
stores (IEC 61966-2-1 transfer function).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

__all__ = ["Material", "srgb_to_linear", "linear_to_srgb"]

RGB = tuple[float, float, float]


def srgb_to_linear(values: "np.ndarray | float") -> np.ndarray:
    """sRGB components (0..1) → linear light (IEC 61966-2-1)."""
    c = np.clip(np.asarray(values, dtype=float), 0.0, 1.0)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(values: "np.ndarray | float") -> np.ndarray:
    """Linear light (0..1) → sRGB components (IEC 61966-2-1)."""
    c = np.clip(np.asarray(values, dtype=float), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


@dataclass(frozen=True)
class Material:
    """A surface's look.

    ``name`` is unique within a build (the table row's name and a digest of the values,
    so two looks never share a name); ``row`` is the material table row it comes from
    and ``surface`` the surface class it dresses (``wall``, ``floor``, ``wood``, ...).
    ``color`` is sRGB in 0..1; ``roughness``, ``metallic`` and ``alpha`` are in 0..1
    (alpha < 1: see-through, blended).
    """

    name: str
    row: str
    surface: str
    color: RGB
    roughness: float
    metallic: float
    alpha: float = 1.0

    @classmethod
    def of(cls, row: str, surface: str, color: RGB, roughness: float, metallic: float,
           alpha: float) -> "Material":
        """A material named by its row and a short digest of its values."""
        color = (round(float(color[0]), 4), round(float(color[1]), 4), round(float(color[2]), 4))
        values = (color, round(float(roughness), 4), round(float(metallic), 4),
                  round(float(alpha), 4))
        digest = hashlib.blake2b(repr((surface, values)).encode(), digest_size=3).hexdigest()
        return cls(f"{row}_{digest}", row, surface, color, values[1], values[2], values[3])

    def __post_init__(self) -> None:
        # Materials are dict keys on the exporters' hot paths (about 1,500 lookups a
        # house), so the hash dataclass would work out on each lookup (that of the tuple
        # of fields: the same value, and equality stays the fields') is kept.
        object.__setattr__(self, "_hash", hash((self.name, self.row, self.surface, self.color,
                                                self.roughness, self.metallic, self.alpha)))

    def __hash__(self) -> int:
        return self._hash  # type: ignore[attr-defined]

    def __getstate__(self) -> dict[str, Any]:
        # string hashes differ between processes: a pickled material hashes afresh
        return {k: v for k, v in self.__dict__.items() if k != "_hash"}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self.__post_init__()

    @property
    def transparent(self) -> bool:
        return self.alpha < 1.0

    @cached_property
    def _linear_rgb(self) -> tuple[float, float, float]:
        """The colour in linear light, worked out once per material (numpy's overhead on
        three values costs more than the conversion; glTF asks once per use)."""
        r, g, b = (float(v) for v in srgb_to_linear(np.asarray(self.color)))
        return (round(r, 6), round(g, 6), round(b, 6))

    def linear_rgba(self) -> list[float]:
        """glTF ``baseColorFactor``: linear RGB and alpha (a new list on each call)."""
        return [*self._linear_rgb, self.alpha]
