"""A tiny 2D drawing model with two renderers: SVG text and an anti-aliased PNG.

The plan exporter composes a :class:`Drawing` from a handful of primitives in paper
coordinates (pixels, y down) and hands it to :func:`render_svg` (hand-written XML; SVG is
just text) and :func:`render_png` (Pillow, drawn at ``supersample`` times the size and
averaged back down, which gives smooth edges without matplotlib).

Both renderers see the same primitives, so the SVG and the PNG of a plan show exactly
the same thing. Text is measured with the PNG's font (DejaVu Sans, Pillow's own font when
DejaVu is not installed) so layout decisions hold for both.
"""

from __future__ import annotations

import io
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache, lru_cache
from typing import Any, Literal, Union
from xml.sax.saxutils import escape, quoteattr

from PIL import Image, ImageDraw, ImageFont

__all__ = [
    "Point",
    "Style",
    "Area",
    "Polyline",
    "Arc",
    "Text",
    "Item",
    "Drawing",
    "text_width",
    "render_svg",
    "render_png",
    "Canvas",
]

Point = tuple[float, float]
"""A paper point (x right, y down) in pixels."""

_FONT_FAMILY = "'DejaVu Sans', Verdana, Arial, sans-serif"
_ARC_SEGMENTS_PER_RADIAN = 12


@dataclass(frozen=True)
class Style:
    """How a primitive is painted. Colours are ``#rrggbb``; ``dash`` is an on/off
    pattern in pixels; ``opacity`` applies to the fill."""

    fill: str | None = None
    stroke: str | None = None
    width: float = 1.0
    dash: tuple[float, ...] = ()
    opacity: float = 1.0


@dataclass(frozen=True)
class Area:
    """A filled region: the first ring is the outline, further rings are holes."""

    rings: tuple[tuple[Point, ...], ...]
    style: Style
    css_class: str = ""


@dataclass(frozen=True)
class Polyline:
    """An open (or ``closed``) line through ``points``."""

    points: tuple[Point, ...]
    style: Style
    closed: bool = False
    css_class: str = ""


@dataclass(frozen=True)
class Arc:
    """A circular arc around ``center`` from angle ``start`` to ``end`` (radians, paper
    frame: 0 along +x, π/2 along +y, i.e. clockwise on screen); |end − start| < π."""

    center: Point
    radius: float
    start: float
    end: float
    style: Style
    css_class: str = ""

    def points(self) -> list[Point]:
        steps = max(2, math.ceil(abs(self.end - self.start) * _ARC_SEGMENTS_PER_RADIAN))
        cx, cy = self.center
        return [(cx + self.radius * math.cos(a), cy + self.radius * math.sin(a))
                for a in (self.start + (self.end - self.start) * k / steps
                          for k in range(steps + 1))]


@dataclass(frozen=True)
class Text:
    """A line of text; ``position`` is the anchor point on the baseline, ``angle`` 0
    (horizontal) or 90 (reading bottom to top)."""

    position: Point
    text: str
    size: float
    fill: str = "#222222"
    anchor: Literal["start", "middle", "end"] = "middle"
    bold: bool = False
    angle: Literal[0, 90] = 0
    css_class: str = ""


Item = Union[Area, Polyline, Arc, Text]


@dataclass
class Drawing:
    """A page: its size in pixels, a background colour, a title and named layers of
    primitives painted in insertion order."""

    width: float
    height: float
    title: str
    background: str = "#ffffff"
    layers: dict[str, list[Item]] = field(default_factory=dict)

    def add(self, layer: str, item: Item) -> None:
        self.layers.setdefault(layer, []).append(item)


# -- fonts ------------------------------------------------------------------------------

@cache
def _font(size_px: int, bold: bool) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
    try:
        return ImageFont.truetype(name, size_px)
    except OSError:  # DejaVu not installed: Pillow's bundled font keeps output possible
        return ImageFont.load_default(size_px)


@lru_cache(maxsize=4096)
def text_width(text: str, size: float, *, bold: bool = False) -> float:
    """Width in pixels of ``text`` at font size ``size`` (pixels); remembered, as a plan
    measures the same labels at several sizes while it looks for room."""
    scale = 8
    return _font(max(1, round(size * scale)), bold).getlength(text) / scale


# -- SVG --------------------------------------------------------------------------------

def _num(value: float) -> str:
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _path_data(rings: Sequence[Sequence[Point]], closed: bool) -> str:
    parts = []
    for ring in rings:
        head, *rest = ring
        parts.append(f"M{_num(head[0])} {_num(head[1])}"
                     + "".join(f"L{_num(x)} {_num(y)}" for x, y in rest)
                     + ("Z" if closed else ""))
    return "".join(parts)


@cache
def _style_attrs(style: Style) -> str:
    """The SVG paint attributes of ``style``; remembered, as a page has a few dozen
    styles for thousands of items."""
    attrs = [f'fill="{style.fill or "none"}"']
    if style.fill and style.opacity < 1.0:
        attrs.append(f'fill-opacity="{_num(style.opacity)}"')
    if style.stroke:
        attrs.append(f'stroke="{style.stroke}" stroke-width="{_num(style.width)}" '
                     f'stroke-linejoin="round" stroke-linecap="round"')
        if style.dash:
            attrs.append(f'stroke-dasharray="{" ".join(_num(d) for d in style.dash)}"')
    return " ".join(attrs)


@cache
def _class_attr(css_class: str) -> str:
    return f" class={quoteattr(css_class)}" if css_class else ""


def _svg_item(item: Item) -> str:
    if isinstance(item, Area):
        return (f'<path{_class_attr(item.css_class)} d="{_path_data(item.rings, True)}" '
                f'fill-rule="evenodd" {_style_attrs(item.style)}/>')
    if isinstance(item, Polyline):
        return (f'<path{_class_attr(item.css_class)} d="{_path_data([item.points], item.closed)}" '
                f'{_style_attrs(item.style)}/>')
    if isinstance(item, Arc):
        points = item.points()
        (x0, y0), (x1, y1) = points[0], points[-1]
        sweep = 1 if item.end > item.start else 0
        r = _num(item.radius)
        return (f'<path{_class_attr(item.css_class)} d="M{_num(x0)} {_num(y0)}A{r} {r} 0 0 '
                f'{sweep} {_num(x1)} {_num(y1)}" {_style_attrs(item.style)}/>')
    x, y = item.position
    rotate = f' transform="rotate(-90 {_num(x)} {_num(y)})"' if item.angle == 90 else ""
    weight = ' font-weight="bold"' if item.bold else ""
    return (f'<text{_class_attr(item.css_class)} x="{_num(x)}" y="{_num(y)}" '
            f'font-size="{_num(item.size)}"{weight} text-anchor="{item.anchor}" '
            f'fill="{item.fill}"{rotate}>{escape(item.text)}</text>')


def render_svg(drawing: Drawing) -> str:
    """The drawing as a standalone SVG 1.1 document (UTF-8 text)."""
    w, h = _num(drawing.width), _num(drawing.height)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" '
        f'viewBox="0 0 {w} {h}" font-family="{_FONT_FAMILY}">',
        f"<title>{escape(drawing.title)}</title>",
        f'<rect width="{w}" height="{h}" fill="{drawing.background}"/>',
    ]
    for name, items in drawing.layers.items():
        lines.append(f"<g id={quoteattr(name)}>")
        lines.extend(_svg_item(item) for item in items)
        lines.append("</g>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


# -- PNG --------------------------------------------------------------------------------

@cache
def _rgba(color: str, opacity: float = 1.0) -> tuple[int, int, int, int]:
    """``#rrggbb`` and an opacity as Pillow's RGBA ink; remembered, as a page asks for
    its handful of colours some thousand times."""
    return (int(color[1:3], 16), int(color[3:5], 16), int(color[5:7], 16), round(255 * opacity))


def _dashes(points: Sequence[Point], pattern: Sequence[float]) -> list[list[Point]]:
    """Split a polyline into the 'on' pieces of a dash pattern."""
    pieces: list[list[Point]] = []
    index, left, on = 0, pattern[0], True
    current: list[Point] = [points[0]]
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        length, done = math.hypot(x1 - x0, y1 - y0), 0.0
        while length - done > left:
            done += left
            t = done / length
            p = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t)
            if on:
                pieces.append(current + [p])
            current = [p]
            on = not on
            index = (index + 1) % len(pattern)
            left = pattern[index]
        left -= length - done
        current.append((x1, y1))
    if on and len(current) > 1:
        pieces.append(current)
    return pieces


def _ends(piece: Sequence[Point]) -> Sequence[Point]:
    """The ends of a stroked piece that get a round cap: a closed ring's two ends are
    one point, capped once (the page is painted, not blended, so a second disc of the
    same ink would change no pixel)."""
    return (piece[0],) if piece[0] == piece[-1] else (piece[0], piece[-1])


class Canvas:
    """A supersampled page kept between :func:`render_png` calls, so the pages of one
    export (a plan per floor, the same size) share one image: painting a page blank
    again is a fill of memory already in use, where a fresh image of some 36 MB costs
    about four times as much in page faults. Same pixels as a new page."""

    def __init__(self) -> None:
        self._image: Image.Image | None = None

    def blank(self, size: tuple[int, int], color: tuple[int, int, int, int]) -> Image.Image:
        """An RGBA page of ``size`` filled with ``color``."""
        if self._image is None or self._image.size != size:
            self._image = Image.new("RGBA", size, color)
        else:
            self._image.paste(color, (0, 0, *size))
        return self._image


class _PngPainter:
    def __init__(self, drawing: Drawing, scale: float, canvas: Canvas):
        self.scale = scale
        size = (round(drawing.width * scale), round(drawing.height * scale))
        self.image = canvas.blank(size, _rgba(drawing.background))
        self.draw = ImageDraw.Draw(self.image, "RGBA")

    def _pts(self, points: Sequence[Point]) -> list[Point]:
        return [(x * self.scale, y * self.scale) for x, y in points]

    def _stroke(self, points: Sequence[Point], style: Style) -> None:
        if not style.stroke or len(points) < 2:
            return
        width = max(1, round(style.width * self.scale))
        pieces = (_dashes(points, [d * self.scale for d in style.dash]) if style.dash
                  else [list(points)])
        ink, r = _rgba(style.stroke), width / 2
        for piece in pieces:
            self.draw.line(piece, fill=ink, width=width, joint="curve")
            if width > 2:  # round caps, as in the SVG
                for x, y in _ends(piece):
                    self.draw.ellipse((x - r, y - r, x + r, y + r), fill=ink)

    def area(self, item: Area) -> None:
        rings = [self._pts(r) for r in item.rings]
        if item.style.fill:
            fill = _rgba(item.style.fill, item.style.opacity)
            if len(rings) == 1:
                self.draw.polygon(rings[0], fill=fill)
            else:  # holes: paint through a mask, only over the box the outline covers
                mask = Image.new("L", self.image.size, 0)
                mask_draw = ImageDraw.Draw(mask)
                mask_draw.polygon(rings[0], fill=fill[3])
                for hole in rings[1:]:
                    mask_draw.polygon(hole, fill=0)
                box = mask.getbbox()
                if box is not None:
                    layer = Image.new("RGBA", (box[2] - box[0], box[3] - box[1]), fill)
                    self.image.paste(layer, box, mask.crop(box))
        for ring in rings:
            self._stroke(ring + ring[:1], item.style)

    def polyline(self, item: Polyline) -> None:
        points = list(item.points) + ([item.points[0]] if item.closed else [])
        self._stroke(self._pts(points), item.style)

    def arc(self, item: Arc) -> None:
        self._stroke(self._pts(item.points()), item.style)

    def text(self, item: Text) -> None:
        size_px = max(1, round(item.size * self.scale))
        anchor = {"start": "ls", "middle": "ms", "end": "rs"}[item.anchor]
        x, y = item.position[0] * self.scale, item.position[1] * self.scale
        if item.angle == 0:
            self.draw.text((x, y), item.text, font=_font(size_px, item.bold),
                           fill=_rgba(item.fill), anchor=anchor)
            return
        turned, (ax, ay) = _turned_text(item.text, size_px, item.bold, anchor, item.fill)
        self.image.alpha_composite(turned, (round(x - ax), round(y - ay)))


@lru_cache(maxsize=256)
def _turned_text(text: str, size_px: int, bold: bool, anchor: str,
                 fill: str) -> tuple[Image.Image, tuple[float, float]]:
    """``text`` reading bottom to top on a transparent image, and where its anchor lies
    on it.

    The text is drawn horizontally on a scratch image at whole pixels and turned; as
    nothing in that depends on where the label goes on the page, the image is kept and
    a repeated label (a plan's chairs, a floor's beds) is drawn once. Callers only read
    it. A label image is some 3 to 15 kB, so the kept ones stay within a few MB.
    """
    font = _font(size_px, bold)
    left, top, right, bottom = font.getbbox(text, anchor=anchor)
    pad = 2
    size = (int(right - left) + 2 * pad, int(bottom - top) + 2 * pad)  # FreeType: whole pixels
    scratch = Image.new("RGBA", size, (0, 0, 0, 0))
    ImageDraw.Draw(scratch).text((pad - left, pad - top), text, font=font, fill=_rgba(fill),
                                 anchor=anchor)
    # the anchor sat at (pad - left, pad - top) in the scratch image; after a
    # counter-clockwise quarter turn it sits at (pad - top, width - pad + left)
    return scratch.rotate(90, expand=True), (pad - top, scratch.width - (pad - left))


def _reduce_rgb(image: Image.Image, factor: int) -> Image.Image:
    """The colour of ``image`` (RGBA) averaged over ``factor`` × ``factor`` blocks, as RGB.

    The page's alpha is the painter's bookkeeping (what an opacity or a text edge left
    behind), not part of the picture: the PNG keeps red, green and blue. Pillow's public
    ``Image.reduce`` averages an RGBA image premultiplied (two conversions of the whole
    supersampled canvas and a weighting by alpha); its core box average treats each band
    on its own, so averaging first and dropping alpha on the small image gives the bytes
    of ``image.convert("RGB").reduce(factor)`` without a pass over the large canvas.
    The core call is the one ``Image.reduce`` makes for every mode without alpha; a
    Pillow without it (the core is not public API) gets the public, slower route.
    """
    core = _core_reduce(image)
    if core is None:
        return image.convert("RGB").reduce(factor)
    return image._new(core((factor, factor), (0, 0, *image.size))).convert("RGB")


def _core_reduce(image: Image.Image) -> Any:
    """Pillow's core box average of ``image`` (what ``Image.reduce`` calls), or None."""
    if not hasattr(image, "_new"):
        return None
    return getattr(getattr(image, "im", None), "reduce", None)


def render_png(drawing: Drawing, *, supersample: int = 3, canvas: Canvas | None = None) -> bytes:
    """The drawing as PNG bytes (RGB), anti-aliased by drawing at ``supersample`` × size
    and averaging each ``supersample`` × ``supersample`` block of pixels; ``canvas``, when
    given, lends the large page (pass one :class:`Canvas` to all pages of an export).

    Raises
    ------
    ValueError
        The page size is not a whole number of pixels.
    """
    if drawing.width != int(drawing.width) or drawing.height != int(drawing.height):
        raise ValueError(f"page size {drawing.width} × {drawing.height} must be whole pixels")
    painter = _PngPainter(drawing, supersample, canvas or Canvas())
    for items in drawing.layers.values():
        for item in items:
            if isinstance(item, Area):
                painter.area(item)
            elif isinstance(item, Polyline):
                painter.polyline(item)
            elif isinstance(item, Arc):
                painter.arc(item)
            else:
                painter.text(item)
    final = _reduce_rgb(painter.image, supersample)
    buffer = io.BytesIO()
    final.save(buffer, format="PNG")
    return buffer.getvalue()
