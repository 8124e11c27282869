"""Property: every split tiles its parent exactly, whatever the seed and the lot.

Over random seeds and lots (rectangles and L shapes), a grammar of splits with absolute,
floating, relative and repeated parts on masses and faces is derived; for every split
the pieces must cover the parent with no gap and no overlap. The checker is independent
of the splitting code: it slices the pieces into horizontal layers at every base and top
and compares, per layer, the sum of footprint areas, the area of their union and the
parent footprint (faces: the same in the face's plane).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st
from shapely.geometry import Polygon, box
from shapely.ops import unary_union

from cga.evaluator import derive
from cga.parser import parse
from cga.shape import Face, Mass

GRAMMAR = """\
Variables:
  height = [6;15];
  floorHeight = [2.5;4];
  bay = [1;3];
Rules:
Lot --> extrude(height) Body
Body --> repeated_split("y", floorHeight){ Ground, Upper }
Ground --> split("x"){ [1;3] : Shop | ~1 : Hall | '0.2 : Stair }
Upper --> 50% : split("z"){ ~bay : Flat }*
        | else : split("x"){ 2 : Wing | ~1 : Core | [0.5;4] : Wing }
Flat --> split("y"){ ~1 : Room | 0.3 : Slab }
Core --> component_split("side_faces"){ Wall }
Wall --> split("x"){ ~1 : Panel | 0.5 : Joint }*
"""
SPLIT_PARENTS = {"Body", "Ground", "Upper", "Flat", "Wall"}
TOL = 1e-6


@st.composite
def lots(draw):
    width = draw(st.floats(6, 40))
    depth = draw(st.floats(6, 40))
    if not draw(st.booleans()):
        return box(0, 0, width, depth)
    notch_x = draw(st.floats(0.25, 0.75)) * width
    notch_z = draw(st.floats(0.25, 0.75)) * depth
    return Polygon([(0, 0), (width, 0), (width, notch_z), (notch_x, notch_z), (notch_x, depth),
                    (0, depth)])


def check_mass_tiling(parent: Mass, pieces: list[Mass], where: str) -> None:
    levels = sorted({parent.base, parent.base + parent.height}
                    | {p.base for p in pieces} | {p.base + p.height for p in pieces})
    volume = sum(p.footprint.area * p.height for p in pieces)
    assert abs(volume - parent.footprint.area * parent.height) <= TOL * max(1.0, volume), where
    for low, high in zip(levels, levels[1:]):
        if high - low <= TOL:
            continue
        middle = (low + high) / 2
        layer = [p.footprint for p in pieces if p.base < middle < p.base + p.height]
        union = unary_union(layer)
        total = sum(f.area for f in layer)
        assert abs(total - union.area) <= TOL * max(1.0, total), f"{where}: overlap at y={middle}"
        assert union.symmetric_difference(parent.footprint).area <= TOL * max(1.0, total), \
            f"{where}: gap at y={middle}"


def _plane_polygon(vertices, origin, u, v) -> Polygon:
    rel = np.asarray(vertices, dtype=float) - origin
    return Polygon(np.column_stack([rel @ u, rel @ v]))


def check_face_tiling(parent: Face, pieces: list[Face], where: str) -> None:
    origin = np.asarray(parent.vertices[0], dtype=float)
    normal = parent.normal()
    u = np.asarray(parent.vertices[1], dtype=float) - origin
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    whole = _plane_polygon(parent.vertices, origin, u, v)
    parts = []
    for piece in pieces:
        offsets = (np.asarray(piece.vertices, dtype=float) - origin) @ normal
        assert np.allclose(offsets, 0, atol=TOL), f"{where}: piece leaves the face's plane"
        assert np.allclose(piece.normal(), normal, atol=TOL), f"{where}: piece turned over"
        parts.append(_plane_polygon(piece.vertices, origin, u, v))
    union = unary_union(parts)
    total = sum(p.area for p in parts)
    assert abs(total - union.area) <= TOL * max(1.0, total), f"{where}: overlap"
    assert union.symmetric_difference(whole).area <= TOL * max(1.0, total), f"{where}: gap"


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), lot=lots())
def test_splits_tile_their_parent(seed, lot):
    derivation = derive(parse(GRAMMAR, "props.grammar"), lot, seed=seed)
    checked = 0
    for node in derivation.root.walk():
        if node.shape.symbol not in SPLIT_PARENTS or not node.children:
            continue
        where = f"seed {seed}, {node.shape.path_name}"
        pieces = [child.shape.geometry for child in node.children]
        if isinstance(node.shape.geometry, Mass):
            check_mass_tiling(node.shape.geometry, pieces, where)
        else:
            check_face_tiling(node.shape.geometry, pieces, where)
        checked += 1
    assert checked >= 3
    terminal_volume = sum(t.geometry.footprint.area * t.geometry.height
                          for t in derivation.terminals if isinstance(t.geometry, Mass))
    assert terminal_volume <= lot.area * derivation.variables["height"] * (1 + TOL)
