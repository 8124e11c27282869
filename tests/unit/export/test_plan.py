"""Floor plans: well-formed SVG with the right symbols, a PNG that shows the same plan."""

from __future__ import annotations

import io
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from shapely.geometry import Point, Polygon

from cga.export.drawing import Arc, Drawing, Polyline, Style, Text, render_png, render_svg
from cga.export.palette import hex_color, room_color
from cga.export.plan import export_plans

SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def plans(small_scene, tmp_path_factory):
    scene, nodes = small_scene
    out = tmp_path_factory.mktemp("plans")
    return scene, export_plans(scene, nodes, out, "house")


def _by_class(root, css_class):
    return [e for e in root.iter() if css_class in e.get("class", "").split()]


def test_one_svg_and_png_per_floor(plans):
    _, paths = plans
    assert sorted(p.name for p in paths) == ["house.floor0.png", "house.floor0.svg",
                                             "house.floor1.png", "house.floor1.svg"]


@pytest.mark.parametrize("floor", [0, 1])
def test_svg_is_well_formed_with_one_label_per_room(plans, floor):
    scene, paths = plans
    plan = scene.floors[floor]
    root = ET.parse(next(p for p in paths if p.name == f"house.floor{floor}.svg")).getroot()
    assert root.tag == f"{SVG}svg"
    labels = [e.text for e in _by_class(root, "room-label")]
    assert sorted(labels) == sorted(r.type for r in plan.rooms)
    areas = [e.text for e in _by_class(root, "room-area")]
    assert sorted(areas) == sorted(f"{r.area:.1f} m²" for r in plan.rooms)
    assert len(_by_class(root, "door-swing")) == len(plan.doors)
    assert len(_by_class(root, "door-leaf")) == len(plan.doors)
    assert len(_by_class(root, "window")) == len(plan.windows)
    assert len(_by_class(root, "front-door")) == (1 if plan.front_door() else 0)
    solid = [f for f in plan.furniture if not f.is_detail]
    assert len(_by_class(root, "furniture")) == len(solid)
    assert len(_by_class(root, "furniture-label")) == len(solid)
    assert _by_class(root, "scale-bar") and _by_class(root, "north")
    assert "floor" in root.find(f"{SVG}title").text


def test_rooms_filled_with_their_type_colour(plans):
    _, paths = plans
    root = ET.parse(next(p for p in paths if p.name == "house.floor0.svg")).getroot()
    fills = {e.get("fill") for e in _by_class(root, "room")}
    assert fills == {hex_color(room_color(t)) for t in ("Livingroom", "Kitchen", "Bathroom")}


def test_png_matches_the_svg_page(plans):
    _, paths = plans
    svg = ET.parse(next(p for p in paths if p.name == "house.floor0.svg")).getroot()
    image = Image.open(next(p for p in paths if p.name == "house.floor0.png"))
    assert image.size == (int(svg.get("width")), int(svg.get("height")))
    pixels = np.asarray(image.convert("RGB")).reshape(-1, 3)
    kitchen = np.array([int(hex_color(room_color("Kitchen"))[i:i + 2], 16) for i in (1, 3, 5)])
    wall = np.array([0x35, 0x31, 0x2D])
    assert (np.abs(pixels - kitchen).sum(axis=1) < 6).sum() > 5000
    assert (np.abs(pixels - wall).sum(axis=1) < 6).sum() > 5000


def _points(d):
    return [tuple(map(float, chunk.split())) for chunk in re.split(r"[MLZ]", d) if chunk.strip()]


@pytest.mark.parametrize("floor", [0, 1])
def test_each_label_sits_in_the_room_of_its_colour(plans, floor):
    _, paths = plans
    root = ET.parse(next(p for p in paths if p.name == f"house.floor{floor}.svg")).getroot()
    rooms = [(e.get("fill"), Polygon(_points(e.get("d")))) for e in _by_class(root, "room")]
    for label in _by_class(root, "room-label"):
        where = Point(float(label.get("x")), float(label.get("y")))
        holders = [fill for fill, shape in rooms if shape.contains(where)]
        assert holders == [hex_color(room_color(label.text))]


def test_renderers_agree_on_primitives():
    drawing = Drawing(width=120, height=80, title="t & <t>")
    drawing.add("a", Polyline(((10, 10), (110, 10)), Style(stroke="#000000", width=4,
                                                             dash=(10, 10))))
    drawing.add("a", Arc((60, 40), 30, 0.0, 1.5, Style(stroke="#ff0000", width=3)))
    drawing.add("a", Text((60, 70), "x<y", 12, angle=90))
    svg = ET.fromstring(render_svg(drawing))
    assert svg.find(f"{SVG}title").text == "t & <t>"
    arc = svg.findall(f".//{SVG}path")[1].get("d")
    assert arc.startswith("M90 40A30 30 0 0 1")
    image = np.asarray(Image.open(io.BytesIO(render_png(drawing))).convert("RGB")).astype(int)
    assert image.shape == (80, 120, 3)
    # dashes: ink at x = 15 (on), paper at x = 25 (off) on the line y = 10
    assert image[10, 15].sum() < 200 and image[10, 25].sum() > 600
    # the arc starts at angle 0 (x = 90, y = 40) and bends clockwise on screen to y > 40
    assert image[40, 90, 0] > 200 and image[40, 90, 1] < 120
    assert image[60, 82, 0] > 200 and image[60, 82, 1] < 120  # angle 0.75: (81.9, 60.4)


def _old_png_pixels(drawing, scale=3):
    """The page painted the plain way: a holed area pasted through a whole-canvas layer
    and mask, then the whole supersampled RGBA canvas converted to RGB and averaged."""
    from PIL import ImageDraw

    size = (drawing.width * scale, drawing.height * scale)
    image = Image.new("RGBA", size, (255, 255, 255, 255))
    draw = ImageDraw.Draw(image, "RGBA")
    for item in (i for items in drawing.layers.values() for i in items):
        rings = [[(x * scale, y * scale) for x, y in ring] for ring in item.rings]
        color = item.style.fill
        fill = (int(color[1:3], 16), int(color[3:5], 16), int(color[5:7], 16),
                round(255 * item.style.opacity))
        if len(rings) == 1:
            draw.polygon(rings[0], fill=fill)
            continue
        mask = Image.new("L", size, 0)
        ImageDraw.Draw(mask).polygon(rings[0], fill=255)
        for hole in rings[1:]:
            ImageDraw.Draw(mask).polygon(hole, fill=0)
        image.paste(Image.new("RGBA", size, fill), (0, 0),
                    Image.composite(Image.new("L", size, fill[3]), mask, mask))
    return np.asarray(image.convert("RGB").reduce(scale))


def test_png_of_areas_with_holes_matches_whole_canvas_painting():
    from cga.export.drawing import Area

    drawing = Drawing(width=90, height=70, title="holes")
    drawing.add("a", Area((((5.3, 4.1), (60.2, 8.7), (44.9, 66.6)),), Style(fill="#3070a0",
                                                                           opacity=0.72)))
    outer = ((10.5, 10.5), (80.25, 12.0), (78.0, 60.4), (12.2, 58.0))
    holes = (((20.1, 20.6), (40.3, 21.0), (30.0, 40.7)), ((50.5, 30.2), (70.0, 30.0),
                                                        (70.0, 50.5), (50.0, 49.9)))
    drawing.add("a", Area((outer, *holes), Style(fill="#c0392b", opacity=0.5)))
    drawing.add("a", Area((outer, holes[1]), Style(fill="#35312d")))
    png = Image.open(io.BytesIO(render_png(drawing)))
    assert png.mode == "RGB"
    assert np.array_equal(np.asarray(png), _old_png_pixels(drawing))


def test_colour_averaged_before_alpha_is_dropped_equals_dropped_then_averaged():
    from cga.export.drawing import _reduce_rgb

    rng = np.random.default_rng(7)
    for width, height in ((30, 21), (31, 23)):  # whole blocks and a ragged edge
        page = Image.fromarray(rng.integers(0, 256, (height, width, 4), dtype=np.uint8), "RGBA")
        expected = page.convert("RGB").reduce(3)
        assert _reduce_rgb(page, 3).tobytes() == expected.tobytes()



def test_a_pillow_without_the_core_reduce_gets_the_same_bytes(monkeypatch):
    from cga.export import drawing

    rng = np.random.default_rng(8)
    page = Image.fromarray(rng.integers(0, 256, (23, 31, 4), dtype=np.uint8), "RGBA")
    monkeypatch.setattr(drawing, "_core_reduce", lambda image: None)
    assert drawing._reduce_rgb(page, 3).tobytes() == page.convert("RGB").reduce(3).tobytes()



def test_a_room_with_vertices_a_round_off_apart_erodes_without_a_warning():
    import warnings

    import shapely.wkt

    from cga.export.plan import _erode

    # free floor of a 20-storey house's room: a cut at 13.8 meets a wall at
    # 13.799999999999999, and door swings round its corners
    text = (Path(__file__).resolve().parents[2] / "data" / "plan"
            / "room_with_round_off_vertices.wkt").read_text()
    region = shapely.wkt.loads(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit = _erode(region, 0.5025685864825581, 0.19372093023255813)
    assert fit.area > 0 and region.buffer(1e-6).contains(fit)
