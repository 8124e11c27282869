"""Make the README's picture of one rendered view: RGB, depth and semantic mask side by side.

Reads a view of a ``<name>.render/`` folder the way a loader does (the three PNGs), colours
the depth (near yellow, far blue, 0.5–6 m) and the semantic mask (wall grey, floor brown,
ceiling white, other classes a colour from a hash of their id, nothing black) and writes
one PNG. The README's picture is::

    cga build demos/house.grammar --seed 0 --out /tmp/house --export render --no-physics
    python scripts/render_triple.py /tmp/house/house.render floor0_room3_0 docs/images/render-triple.png
"""

from __future__ import annotations

import argparse
import hashlib
from pathlib import Path

import numpy as np
from PIL import Image

_RAMP = np.array([[253, 231, 37], [94, 201, 98], [33, 145, 140], [59, 82, 139], [68, 1, 84]],
                 dtype=float)
_FIXED = {0: (0, 0, 0), 1: (200, 200, 200), 2: (120, 90, 60), 3: (240, 240, 250)}
_PANEL = (420, 315)
_GAP = 10


def depth_colors(millimetres: np.ndarray, near: float = 0.5, far: float = 6.0) -> np.ndarray:
    """``uint8[h, w, 3]``: depth on a yellow-to-blue ramp; black where there is none."""
    metres = millimetres.astype(float) / 1000.0
    t = np.clip((metres - near) / (far - near), 0.0, 1.0) * (len(_RAMP) - 1)
    low = np.minimum(t.astype(int), len(_RAMP) - 2)
    mix = (t - low)[..., None]
    out = (_RAMP[low] * (1 - mix) + _RAMP[low + 1] * mix).astype(np.uint8)
    out[millimetres == 0] = 0
    return out


def class_colors(classes: np.ndarray) -> np.ndarray:
    """``uint8[h, w, 3]``: one colour per class id."""
    ids = np.unique(classes)
    palette = {int(c): _FIXED.get(int(c)) or tuple(hashlib.md5(str(int(c)).encode()).digest()[:3])
               for c in ids}
    out = np.zeros((*classes.shape, 3), dtype=np.uint8)
    for c, color in palette.items():
        out[classes == c] = color
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="a <name>.render folder")
    parser.add_argument("view", help="the view's name, e.g. floor0_room3_0")
    parser.add_argument("out", type=Path, help="the PNG to write")
    args = parser.parse_args()
    read = lambda kind: np.asarray(Image.open(args.folder / f"{args.view}.{kind}.png"))  # noqa: E731
    panels = [Image.fromarray(read("rgb")).resize(_PANEL, Image.Resampling.LANCZOS),
              Image.fromarray(depth_colors(read("depth"))).resize(_PANEL, Image.Resampling.LANCZOS),
              Image.fromarray(class_colors(read("semantic"))).resize(_PANEL, Image.Resampling.NEAREST)]
    picture = Image.new("RGB", (3 * _PANEL[0] + 2 * _GAP, _PANEL[1]), (255, 255, 255))
    for k, panel in enumerate(panels):
        picture.paste(panel, (k * (_PANEL[0] + _GAP), 0))
    picture.save(args.out, optimize=True)


if __name__ == "__main__":
    main()
