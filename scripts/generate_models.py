"""Generate the shipped furniture models, ``models/<name>.obj``, from convex parts.

The OBJ files are build products of this script: change a model here and rerun it, never
edit the files by hand (a test regenerates them and compares the bytes). Every model is
a handful of convex solids (boxes, few-sided cylinders and frustums, coarse spheres) made
with ``trimesh.creation``, so the physics check can use the parts as a compound body
without a convex decomposition (docs/furniture.md, docs/checks.md).

Conventions of every file (docs/architecture.md "Units and frames", docs/models.md):
metres, y up, front toward −z, origin at the centre of the footprint on the floor (the
lowest point is at y = 0). One OBJ group ``g part_N_<material>`` per part (its material class, e.g.
``part_3_wood``, which the material library dresses); vertex colours
``v x y z r g b`` colour each part; header comments give the model's ``# density`` (kg/m³, chosen so
the parts weigh what the real piece weighs) and main ``# color``. Output is deterministic:
rerunning gives identical bytes.

Usage::

    python scripts/generate_models.py            # rewrite models/*.obj
    python scripts/generate_models.py --out DIR  # write elsewhere
    python scripts/generate_models.py --check    # exit 1 if models/ is out of date
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import NamedTuple
from pathlib import Path

import numpy as np
import trimesh

from cga.fsutil import atomic_write

__all__ = ["MODELS", "Model", "Part", "obj_text", "render_models", "stale_files",
           "write_models", "main"]

MODELS_DIR = Path(__file__).resolve().parent.parent / "models"

Color = tuple[float, float, float]
Vec3 = tuple[float, float, float]



class Finish(NamedTuple):
    """A part's surface: its colour (RGB in 0..1) and its material class, which names
    the part's OBJ group (``g part_3_wood``) so the material library can dress it
    (docs/appearance.md)."""

    color: Color
    material: str


# Palette: colours with the material class of the surface they are.
OAK = Finish((0.72, 0.55, 0.36), "wood")
WALNUT = Finish((0.42, 0.28, 0.18), "wood")
WHITE = Finish((0.93, 0.93, 0.91), "paint")  # lacquered boards, painted doors and frames
SHEET = Finish(WHITE.color, "fabric")  # a mattress
SEAT = Finish(WHITE.color, "plastic")  # a toilet seat
CERAMIC = Finish((0.97, 0.97, 0.96), "ceramic")
LINEN = Finish((0.90, 0.87, 0.80), "fabric")
BLUE_FABRIC = Finish((0.29, 0.39, 0.55), "fabric")
GREY_FABRIC = Finish((0.50, 0.50, 0.52), "fabric")
CHARCOAL = Finish((0.16, 0.16, 0.17), "plastic")
IRON = Finish(CHARCOAL.color, "metal")  # dark metal legs and bases
BLACK = Finish((0.05, 0.05, 0.06), "plastic")
HOB = Finish(BLACK.color, "glass")  # a glass-ceramic hob, an oven window
STEEL = Finish((0.75, 0.76, 0.78), "metal")
DARK_STEEL = Finish((0.45, 0.46, 0.48), "metal")
GLASS = Finish((0.70, 0.85, 0.90), "glass")
LEAF = Finish((0.22, 0.50, 0.20), "plant")
DARK_LEAF = Finish((0.15, 0.38, 0.14), "plant")
TERRACOTTA = Finish((0.72, 0.36, 0.22), "ceramic")
SOIL = Finish((0.30, 0.20, 0.12), "soil")
RUG_RED = Finish((0.60, 0.20, 0.18), "fabric")
RUG_CREAM = Finish((0.88, 0.80, 0.62), "fabric")
SHADE = Finish((0.95, 0.90, 0.75), "fabric")
BOOKS: tuple[Finish, ...] = tuple(Finish(c, "paper") for c in (
    (0.55, 0.15, 0.15), (0.15, 0.30, 0.50), (0.80, 0.65, 0.25), (0.20, 0.45, 0.30),
    (0.45, 0.30, 0.50)))


@dataclass(frozen=True)
class Part:
    """One convex solid of a model and its finish (colour and material class)."""

    mesh: trimesh.Trimesh
    color: Finish


@dataclass(frozen=True)
class Model:
    """A model as built: its parts, its main finish and the real piece's mass (kg)."""

    name: str
    color: Finish
    mass: float
    parts: tuple[Part, ...]


# -- convex primitives -------------------------------------------------------------------

def box(a: Vec3, b: Vec3, color: Finish) -> Part:
    """An axis-aligned box between opposite corners ``a`` and ``b`` (in any order)."""
    return Part(trimesh.creation.box(bounds=np.sort(np.array([a, b], dtype=float), axis=0)),
                color)


def turned_box(size: Vec3, center: Vec3, angle: float, color: Finish) -> Part:
    """A box of ``size`` turned by ``angle`` radians about +y, centred on ``center``."""
    matrix = trimesh.transformations.rotation_matrix(angle, (0.0, 1.0, 0.0))
    matrix[:3, 3] = center
    return Part(trimesh.creation.box(extents=size, transform=matrix), color)


def frustum(x: float, z: float, y0: float, y1: float, r0: float, r1: float, color: Finish,
            sections: int = 8) -> Part:
    """A vertical frustum, radius ``r0`` at ``y0`` to ``r1`` at ``y1`` (a prism if equal)."""
    mesh = trimesh.creation.cylinder(radius=r0, sections=sections,
                                     segment=[(x, y0, z), (x, y1, z)])
    top = np.isclose(mesh.vertices[:, 1], y1)
    axis = np.array([x, 0.0, z])
    vertices = mesh.vertices.copy()
    vertices[top] = axis + (vertices[top] - axis) * np.array([r1 / r0, 1.0, r1 / r0])
    vertices[top, 1] = y1
    return Part(trimesh.Trimesh(vertices, mesh.faces, process=False), color)


def prism(x: float, z: float, y0: float, y1: float, radius: float, color: Finish,
          sections: int = 8) -> Part:
    """A vertical few-sided cylinder standing on ``y0``."""
    return frustum(x, z, y0, y1, radius, radius, color, sections)


def oval(x: float, z: float, y0: float, y1: float, rx: float, rz: float, color: Finish,
         sections: int = 12) -> Part:
    """A vertical cylinder with an elliptic section (radii ``rx`` across, ``rz`` deep)."""
    part = prism(0.0, 0.0, y0, y1, rx, color, sections)
    mesh = part.mesh.copy()
    mesh.vertices = mesh.vertices * np.array([1.0, 1.0, rz / rx]) + np.array([x, 0.0, z])
    return Part(mesh, color)


def knob(x: float, y: float, z0: float, z1: float, radius: float, color: Finish,
         sections: int = 8) -> Part:
    """A cylinder along z between ``z0`` and ``z1`` (knobs, roses, a porthole)."""
    mesh = trimesh.creation.cylinder(radius=radius, sections=sections,
                                     segment=[(x, y, z0), (x, y, z1)])
    return Part(mesh, color)


def ball(center: Vec3, radius: float, color: Finish, squash: float = 1.0) -> Part:
    """A coarse sphere (80 faces), optionally squashed vertically by ``squash``."""
    mesh = trimesh.creation.icosphere(subdivisions=1, radius=radius)
    mesh.vertices = mesh.vertices * np.array([1.0, squash, 1.0]) + np.asarray(center)
    return Part(mesh, color)


def legs(half_x: float, half_z: float, y0: float, y1: float, side: float,
         color: Finish) -> list[Part]:
    """Four square legs of width ``side`` centred at (±half_x, ±half_z)."""
    s = side / 2
    return [box((x - s, y0, z - s), (x + s, y1, z + s), color)
            for x in (-half_x, half_x) for z in (-half_z, half_z)]


# -- shared furniture shapes --------------------------------------------------------------

def bed(name: str, width: float, length: float, head: float, pillows: int,
        mass: float) -> Model:
    """Frame on four legs, mattress, duvet, pillows and a headboard at the back (+z)."""
    w, l = width / 2, length / 2
    foot, back = -l, l - 0.06
    parts = legs(w - 0.05, l - 0.12, 0.0, 0.10, 0.06, WALNUT)
    parts += [
        box((-w, 0.10, foot), (w, 0.32, back), WALNUT),
        box((-w + 0.03, 0.32, foot + 0.03), (w - 0.03, 0.54, back - 0.03), SHEET),
        box((-w + 0.02, 0.54, foot + 0.02), (w - 0.02, 0.57, back - 0.55), BLUE_FABRIC),
        box((-w, 0.0, back), (w, head, l), WALNUT),
    ]
    step = (width - 0.1) / pillows
    for i in range(pillows):
        cx = -w + 0.05 + step * (i + 0.5)
        parts.append(box((cx - step / 2 + 0.03, 0.54, back - 0.42),
                         (cx + step / 2 - 0.03, 0.64, back - 0.06), LINEN))
    return Model(name, WALNUT, mass, tuple(parts))


def sofa(name: str, width: float, seats: int, color: Finish, mass: float) -> Model:
    """Base on feet, back (+z), two arms and one seat and back cushion per seat."""
    w, d, arm = width / 2, 0.45, 0.16
    parts = [prism(x, z, 0.0, 0.08, 0.025, WALNUT)
             for x in (-w + 0.08, w - 0.08) for z in (-d + 0.07, d - 0.07)]
    parts += [
        box((-w, 0.08, -d), (w, 0.30, d), color),
        box((-w, 0.30, 0.25), (w, 0.85, d), color),
        box((-w, 0.30, -d), (-w + arm, 0.62, 0.25), color),
        box((w - arm, 0.30, -d), (w, 0.62, 0.25), color),
    ]
    step = (width - 2 * arm) / seats
    for i in range(seats):
        x0 = -w + arm + step * i + 0.005
        x1 = x0 + step - 0.01
        parts.append(box((x0, 0.30, -d + 0.02), (x1, 0.44, 0.25), color))
        parts.append(box((x0, 0.44, 0.10), (x1, 0.76, 0.25), GREY_FABRIC))
    return Model(name, color, mass, tuple(parts))


def table(width: float, depth: float, height: float, top: float, leg: float,
          color: Finish) -> list[Part]:
    """Top, four legs inset by their width and four aprons under the top."""
    w, d = width / 2, depth / 2
    lx, lz, y = w - leg, d - leg, height - top
    parts = [box((-w, y, -d), (w, height, d), color)]
    parts += legs(lx, lz, 0.0, y, leg, color)
    parts += [box((-lx, y - 0.10, z - 0.01), (lx, y, z + 0.01), color) for z in (-lz, lz)]
    parts += [box((x - 0.01, y - 0.10, -lz), (x + 0.01, y, lz), color) for x in (-lx, lx)]
    return parts


def carcass(width: float, y0: float, y1: float, z0: float, z1: float,
            color: Finish) -> Part:
    """The closed body of a cabinet between heights ``y0``..``y1`` and depths ``z0``..``z1``."""
    return box((-width / 2, y0, z0), (width / 2, y1, z1), color)


def fronts(columns: int, y0: float, y1: float, width: float, front_z: float,
           color: Finish, handle: Finish, handle_at: str) -> list[Part]:
    """``columns`` door or drawer fronts side by side on the face at ``front_z``, each
    with a bar handle: vertical near the meeting edge (``"edge"``), horizontal at the
    top (``"top"``) or centred (``"middle"``)."""
    w, gap, t = width / 2, 0.005, 0.02
    step = width / columns
    parts = []
    for i in range(columns):
        x0, x1 = -w + step * i + gap, -w + step * (i + 1) - gap
        parts.append(box((x0, y0, front_z - t), (x1, y1, front_z), color))
        hz = (front_z - t - 0.025, front_z - t)
        if handle_at == "edge":
            hx = x1 - 0.05 if i < columns / 2 else x0 + 0.03
            hy = ((y0 + y1) / 2 - 0.15, (y0 + y1) / 2 + 0.15)
            parts.append(box((hx, hy[0], hz[0]), (hx + 0.02, hy[1], hz[1]), handle))
        else:
            cy = y1 - 0.06 if handle_at == "top" else (y0 + y1) / 2
            cx = (x0 + x1) / 2
            parts.append(box((cx - 0.08, cy - 0.01, hz[0]), (cx + 0.08, cy + 0.01, hz[1]),
                             handle))
    return parts


def kitchen_unit(width: float, doors: int) -> list[Part]:
    """Base cabinet on a recessed plinth with door fronts and a worktop at 0.9 m."""
    return [
        carcass(width, 0.0, 0.10, -0.25, 0.30, CHARCOAL),
        carcass(width, 0.10, 0.86, -0.28, 0.30, WHITE),
        *fronts(doors, 0.12, 0.84, width, -0.28, WHITE, STEEL, "top"),
        carcass(width, 0.86, 0.90, -0.33, 0.30, OAK),
    ]


def tap(x: float, z: float, y0: float, reach: float) -> list[Part]:
    """A tap: a vertical pipe at (x, z) from ``y0`` with a spout reaching ``reach`` toward −z."""
    return [prism(x, z, y0, y0 + 0.25, 0.015, STEEL, sections=8),
            box((x - 0.012, y0 + 0.22, z - reach), (x + 0.012, y0 + 0.25, z), STEEL)]


def open_shelving(width: float, height: float, depth: float, boards: int,
                  back: bool, color: Finish) -> list[Part]:
    """Two sides, a top, a plinth, ``boards`` boards and optionally a back panel."""
    w, d, t = width / 2, depth / 2, 0.02
    parts = [box((-w, 0.0, -d), (-w + t, height, d), color),
             box((w - t, 0.0, -d), (w, height, d), color),
             box((-w + t, height - t, -d), (w - t, height, d), color),
             box((-w + t, 0.0, -d + 0.01), (w - t, 0.08, d - 0.01), color)]
    if back:
        parts.append(box((-w + t, 0.08, d - 0.01), (w - t, height - t, d), color))
    pitch = (height - t - 0.08) / (boards + 1)
    for i in range(boards + 1):
        y = 0.08 + pitch * i
        parts.append(box((-w + t, y, -d), (w - t, y + t, d - (0.01 if back else 0)), color))
    return parts


# -- the models ---------------------------------------------------------------------------

def make_bed() -> Model:
    return bed("bed", 0.96, 2.06, 0.90, pillows=1, mass=60)


def make_doublebed() -> Model:
    return bed("doublebed", 1.66, 2.10, 1.00, pillows=2, mass=110)


def make_nightstand() -> Model:
    parts = legs(0.20, 0.17, 0.0, 0.08, 0.03, WALNUT)
    parts += [carcass(0.45, 0.08, 0.55, -0.18, 0.20, WALNUT),
              *fronts(1, 0.34, 0.52, 0.45, -0.18, OAK, STEEL, "middle"),
              *fronts(1, 0.10, 0.32, 0.45, -0.18, OAK, STEEL, "middle")]
    return Model("nightstand", WALNUT, 15, tuple(parts))


def make_wardrobe() -> Model:
    parts = [carcass(0.96, 0.0, 0.08, -0.26, 0.28, CHARCOAL),
             carcass(1.00, 0.08, 2.00, -0.28, 0.30, OAK),
             *fronts(2, 0.10, 1.98, 1.00, -0.28, OAK, STEEL, "edge")]
    return Model("wardrobe", OAK, 90, tuple(parts))


def make_dresser() -> Model:
    parts = legs(0.56, 0.21, 0.0, 0.10, 0.04, WALNUT)
    parts.append(carcass(1.20, 0.10, 0.80, -0.23, 0.25, WALNUT))
    for y0, y1 in ((0.12, 0.33), (0.35, 0.56), (0.58, 0.78)):
        parts += fronts(1, y0, y1, 1.16, -0.23, OAK, STEEL, "middle")
    return Model("dresser", WALNUT, 50, tuple(parts))


def make_desk() -> Model:
    parts = [box((-0.70, 0.72, -0.35), (0.70, 0.75, 0.35), OAK)]
    parts += legs(0.65, 0.30, 0.0, 0.72, 0.05, IRON)
    parts += [box((-0.625, 0.40, 0.30), (0.625, 0.70, 0.32), IRON),
              box((0.15, 0.62, -0.30), (0.60, 0.72, 0.28), OAK),
              box((0.155, 0.625, -0.32), (0.595, 0.715, -0.30), WHITE)]
    return Model("desk", OAK, 30, tuple(parts))


def make_officechair() -> Model:
    parts = []
    for i in range(5):  # five-star base: an arm toward each caster
        angle = math.pi / 2 + 2 * math.pi * i / 5
        ux, uz = math.cos(angle), math.sin(angle)
        parts.append(turned_box((0.05, 0.04, 0.28), (0.14 * ux, 0.08, 0.14 * uz),
                                math.pi / 2 - angle, CHARCOAL))
        parts.append(prism(0.28 * ux, 0.28 * uz, 0.0, 0.06, 0.03, BLACK))
    parts += [
        prism(0.0, 0.0, 0.06, 0.12, 0.05, CHARCOAL),
        prism(0.0, 0.0, 0.12, 0.39, 0.025, STEEL),
        box((-0.10, 0.39, -0.10), (0.10, 0.43, 0.10), CHARCOAL),
        box((-0.25, 0.43, -0.24), (0.25, 0.50, 0.24), BLUE_FABRIC),
        box((-0.03, 0.43, 0.24), (0.03, 0.65, 0.27), CHARCOAL),
        box((-0.23, 0.60, 0.27), (0.23, 1.10, 0.33), BLUE_FABRIC),
    ]
    for side in (-1, 1):
        parts.append(box((side * 0.25, 0.46, -0.02), (side * 0.28, 0.68, 0.02), CHARCOAL))
        parts.append(box((side * 0.235, 0.68, -0.14), (side * 0.295, 0.71, 0.10), CHARCOAL))
    return Model("officechair", BLUE_FABRIC, 15, tuple(parts))


def make_chair() -> Model:
    parts = legs(0.19, 0.20, 0.0, 0.43, 0.035, OAK)
    parts += [box((-0.22, 0.43, -0.23), (0.22, 0.47, 0.23), OAK)]
    parts += [box((x - 0.0175, 0.47, 0.1825), (x + 0.0175, 0.90, 0.2175), OAK)
              for x in (-0.19, 0.19)]
    parts.append(box((-0.1725, 0.62, 0.19), (0.1725, 0.86, 0.21), OAK))
    return Model("chair", OAK, 6, tuple(parts))


def make_diningtable() -> Model:
    return Model("diningtable", OAK, 40, tuple(table(1.60, 0.90, 0.76, 0.04, 0.07, OAK)))


def make_tablebig() -> Model:
    return Model("tablebig", WALNUT, 75, tuple(table(2.20, 1.00, 0.76, 0.05, 0.09, WALNUT)))


def make_sofatable() -> Model:
    parts = table(1.10, 0.60, 0.45, 0.04, 0.05, WALNUT)
    parts.append(box((-0.50, 0.10, -0.25), (0.50, 0.12, 0.25), WALNUT))
    return Model("sofatable", WALNUT, 15, tuple(parts))


def make_sofa() -> Model:
    return sofa("sofa", 2.00, seats=2, color=BLUE_FABRIC, mass=70)


def make_armchair() -> Model:
    return sofa("armchair", 0.85, seats=1, color=BLUE_FABRIC, mass=35)


def make_tvboard() -> Model:
    parts = legs(0.76, 0.16, 0.0, 0.10, 0.04, IRON)
    parts += [carcass(1.60, 0.10, 0.48, -0.18, 0.20, WHITE),
              *fronts(2, 0.12, 0.46, 1.60, -0.18, WHITE, STEEL, "edge"),
              box((-0.15, 0.48, -0.08), (0.15, 0.50, 0.12), BLACK),
              box((-0.03, 0.50, 0.03), (0.03, 0.62, 0.06), BLACK),
              box((-0.61, 0.58, -0.02), (0.61, 1.29, 0.03), BLACK)]
    return Model("tvboard", WHITE, 45, tuple(parts))


def make_bookshelf() -> Model:
    parts = open_shelving(0.80, 1.90, 0.30, boards=4, back=True, color=OAK)
    pitch = (1.90 - 0.02 - 0.08) / 5
    for i in range(5):
        y = 0.10 + pitch * i
        for j, (x0, x1, h) in enumerate(((-0.37, -0.12, 0.26), (-0.05, 0.22, 0.22))):
            parts.append(box((x0, y, -0.11), (x1, y + h, 0.12), BOOKS[(i + 2 * j) % len(BOOKS)]))
    return Model("bookshelf", OAK, 45, tuple(parts))


def make_shelf() -> Model:
    parts = open_shelving(0.80, 1.10, 0.35, boards=2, back=False, color=WHITE)
    pitch = (1.10 - 0.02 - 0.08) / 3
    for i, color in enumerate((LINEN, GREY_FABRIC)):
        y = 0.10 + pitch * i
        parts.append(box((-0.30, y, -0.13), (0.05, y + 0.22, 0.14), color))
    return Model("shelf", WHITE, 20, tuple(parts))


def make_floorlamp() -> Model:
    parts = (prism(0.0, 0.0, 0.0, 0.03, 0.15, IRON, sections=12),
             prism(0.0, 0.0, 0.03, 1.42, 0.012, STEEL, sections=6),
             frustum(0.0, 0.0, 1.40, 1.70, 0.19, 0.13, SHADE, sections=10))
    return Model("floorlamp", SHADE, 6, parts)


def make_rug() -> Model:
    parts = (box((-1.0, 0.0, -0.7), (1.0, 0.01, 0.7), RUG_RED),
             box((-0.8, 0.01, -0.5), (0.8, 0.012, 0.5), RUG_CREAM))
    return Model("rug", RUG_RED, 8, parts)


def make_kitchencounter() -> Model:
    return Model("kitchencounter", WHITE, 60, tuple(kitchen_unit(1.20, doors=2)))


def make_sink() -> Model:
    parts = kitchen_unit(0.80, doors=2)
    parts += [box((-0.25, 0.90, -0.22), (0.25, 0.905, 0.12), STEEL),
              box((-0.21, 0.905, -0.19), (0.21, 0.907, 0.09), DARK_STEEL),
              *tap(0.0, 0.20, 0.90, reach=0.15)]
    return Model("sink", WHITE, 45, tuple(parts))


def make_stove() -> Model:
    parts = [carcass(0.60, 0.0, 0.08, -0.25, 0.30, CHARCOAL),
             carcass(0.60, 0.08, 0.88, -0.28, 0.30, WHITE),
             carcass(0.60, 0.88, 0.90, -0.28, 0.30, HOB)]
    for x, z, r in ((-0.14, -0.13, 0.07), (0.14, -0.13, 0.055), (-0.14, 0.15, 0.055),
                    (0.14, 0.15, 0.07)):
        parts.append(prism(x, z, 0.90, 0.91, r, DARK_STEEL, sections=12))
    parts += [box((-0.28, 0.12, -0.30), (0.28, 0.68, -0.28), WHITE),
              box((-0.20, 0.25, -0.305), (0.20, 0.55, -0.30), HOB),
              box((-0.22, 0.62, -0.34), (0.22, 0.64, -0.31), STEEL),
              box((-0.28, 0.70, -0.29), (0.28, 0.86, -0.28), DARK_STEEL)]
    parts += [knob(x, 0.78, -0.31, -0.29, 0.02, BLACK) for x in (-0.18, -0.06, 0.06, 0.18)]
    return Model("stove", WHITE, 50, tuple(parts))


def make_fridge() -> Model:
    parts = [carcass(0.60, 0.0, 1.85, -0.28, 0.34, WHITE),
             box((-0.295, 0.02, -0.31), (0.295, 0.62, -0.28), WHITE),
             box((-0.295, 0.64, -0.31), (0.295, 1.83, -0.28), WHITE),
             box((0.23, 0.40, -0.35), (0.25, 0.58, -0.31), STEEL),
             box((0.23, 0.90, -0.35), (0.25, 1.30, -0.31), STEEL)]
    return Model("fridge", WHITE, 70, tuple(parts))


def make_toilet() -> Model:
    parts = (box((-0.12, 0.0, -0.15), (0.12, 0.30, 0.20), CERAMIC),
             oval(0.0, -0.06, 0.28, 0.40, 0.18, 0.24, CERAMIC),
             oval(0.0, -0.06, 0.40, 0.42, 0.185, 0.245, SEAT),
             box((-0.19, 0.40, 0.17), (0.19, 0.80, 0.34), CERAMIC),
             prism(0.0, 0.255, 0.80, 0.81, 0.025, STEEL))
    return Model("toilet", CERAMIC, 30, parts)


def make_bathtub() -> Model:
    w, d, t = 0.85, 0.375, 0.08
    parts = [box((-w, 0.0, -d), (w, 0.10, d), CERAMIC),
             box((-w, 0.10, -d), (w, 0.58, -d + t), CERAMIC),
             box((-w, 0.10, d - t), (w, 0.58, d), CERAMIC),
             box((-w, 0.10, -d + t), (-w + t, 0.58, d - t), CERAMIC),
             box((w - t, 0.10, -d + t), (w, 0.58, d - t), CERAMIC),
             *tap(0.60, d - t / 2, 0.58, reach=0.12)]
    return Model("bathtub", CERAMIC, 45, tuple(parts))


def make_shower() -> Model:
    parts = [box((-0.45, 0.0, -0.45), (0.45, 0.06, 0.45), CERAMIC),
             box((-0.45, 0.06, -0.45), (0.45, 2.00, -0.44), GLASS),
             box((-0.45, 0.06, -0.44), (-0.44, 2.00, 0.45), GLASS),
             prism(0.30, 0.43, 0.06, 2.00, 0.012, STEEL, sections=6),
             box((0.29, 1.96, 0.25), (0.31, 1.98, 0.43), STEEL),
             prism(0.30, 0.25, 1.93, 1.96, 0.10, STEEL, sections=12),
             box((0.22, 0.95, 0.41), (0.38, 1.05, 0.45), STEEL)]
    return Model("shower", GLASS, 60, tuple(parts))


def make_washbasin() -> Model:
    parts = [box((-0.09, 0.0, 0.02), (0.09, 0.70, 0.20), CERAMIC),
             box((-0.30, 0.70, -0.24), (0.30, 0.85, 0.24), CERAMIC),
             oval(0.0, -0.03, 0.85, 0.852, 0.20, 0.15, STEEL),
             *tap(0.0, 0.18, 0.85, reach=0.10)]
    return Model("washbasin", CERAMIC, 20, tuple(parts))


def make_washingmachine() -> Model:
    parts = (carcass(0.60, 0.0, 0.85, -0.28, 0.30, WHITE),
             box((-0.29, 0.74, -0.29), (0.29, 0.83, -0.28), STEEL),
             knob(0.18, 0.785, -0.31, -0.29, 0.03, DARK_STEEL),
             knob(0.0, 0.42, -0.31, -0.28, 0.17, GLASS, sections=16),
             knob(0.0, 0.42, -0.315, -0.31, 0.12, CHARCOAL, sections=16))
    return Model("washingmachine", WHITE, 70, parts)


def make_plant() -> Model:
    parts = (frustum(0.0, 0.0, 0.0, 0.32, 0.13, 0.17, TERRACOTTA, sections=10),
             prism(0.0, 0.0, 0.32, 0.33, 0.155, SOIL, sections=10),
             prism(0.0, 0.0, 0.33, 0.60, 0.02, WALNUT, sections=6),
             ball((0.0, 0.82, 0.0), 0.30, LEAF),
             ball((0.14, 0.66, -0.12), 0.15, DARK_LEAF),
             ball((-0.12, 1.00, 0.10), 0.15, DARK_LEAF))
    return Model("plant", LEAF, 12, parts)


def make_door() -> Model:
    parts = [box((-0.45, 0.0, -0.02), (0.45, 2.10, 0.02), WHITE)]
    for side in (-1, 1):  # a rose, a neck and a lever on each face; hinges at -x
        parts += [knob(0.36, 1.05, side * 0.02, side * 0.03, 0.025, STEEL),
                  knob(0.36, 1.05, side * 0.03, side * 0.06, 0.008, STEEL),
                  box((0.25, 1.04, side * 0.05), (0.37, 1.06, side * 0.07), STEEL)]
    return Model("door", WHITE, 25, tuple(parts))


def make_window() -> Model:
    f, d = 0.06, 0.03
    parts = (box((-0.6, 0.0, -d), (0.6, f, d), WHITE),
             box((-0.6, 1.2 - f, -d), (0.6, 1.2, d), WHITE),
             box((-0.6, f, -d), (-0.6 + f, 1.2 - f, d), WHITE),
             box((0.6 - f, f, -d), (0.6, 1.2 - f, d), WHITE),
             box((-0.03, f, -0.025), (0.03, 1.2 - f, 0.025), WHITE),
             box((-0.6 + f, f, -0.005), (-0.03, 1.2 - f, 0.005), GLASS),
             box((0.03, f, -0.005), (0.6 - f, 1.2 - f, 0.005), GLASS))
    return Model("window", WHITE, 30, parts)


MODELS: tuple[Callable[[], Model], ...] = (
    make_bed, make_doublebed, make_nightstand, make_wardrobe, make_dresser, make_desk,
    make_officechair, make_chair, make_diningtable, make_tablebig, make_sofa,
    make_armchair, make_sofatable, make_tvboard, make_bookshelf, make_floorlamp, make_rug,
    make_kitchencounter, make_fridge, make_stove, make_sink, make_toilet, make_bathtub,
    make_shower, make_washbasin, make_washingmachine, make_shelf, make_plant, make_door,
    make_window,
)
"""Every shipped model's builder."""


# -- output -------------------------------------------------------------------------------

def _number(value: float, digits: int) -> str:
    return f"{round(float(value), digits) + 0.0:.{digits}f}"


def obj_text(model: Model) -> str:
    """The OBJ file of ``model``: placed on the floor, footprint centred, parts as groups."""
    meshes = [p.mesh for p in model.parts]
    lo = np.min([m.bounds[0] for m in meshes], axis=0)
    hi = np.max([m.bounds[1] for m in meshes], axis=0)
    offset = -np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])
    volume = sum(float(m.volume) for m in meshes)
    density = round(model.mass / volume)
    size = hi - lo
    lines = [
        f"# cga furniture model: {model.name}",
        "# generated by scripts/generate_models.py: edit the script and rerun it",
        "# metres, y up, front toward -z, origin at the centre of the footprint on the floor",
        f"# size {' '.join(_number(s, 3) for s in size)}",
        f"# density {density}",
        f"# color {' '.join(_number(c, 3) for c in model.color.color)}",
    ]
    first = 1
    for index, part in enumerate(model.parts):
        rgb = " ".join(_number(c, 3) for c in part.color.color)
        lines.append(f"g part_{index}_{part.color.material}")
        lines += [f"v {' '.join(_number(c, 6) for c in vertex)} {rgb}"
                  for vertex in part.mesh.vertices + offset]
        lines += [f"f {' '.join(str(first + i) for i in face)}" for face in part.mesh.faces]
        first += len(part.mesh.vertices)
    return "\n".join(lines) + "\n"


def render_models(builders: Iterable[Callable[[], Model]] = MODELS) -> dict[str, str]:
    """File name → OBJ text of every model."""
    out = {}
    for build in builders:
        model = build()
        out[f"{model.name}.obj"] = obj_text(model)
    return out


def write_models(out_dir: Path) -> list[Path]:
    """Write every model into ``out_dir`` (atomically, file by file); returns the paths."""
    return [atomic_write(Path(out_dir) / name, text) for name, text in render_models().items()]


def stale_files(models_dir: Path) -> list[str]:
    """OBJ files in ``models_dir`` that differ from, are missing from, or are not in the
    generated set."""
    expected = render_models()
    present = {p.name for p in Path(models_dir).glob("*.obj")}
    names = sorted(present | set(expected))
    return [n for n in names if n not in present or n not in expected
            or (Path(models_dir) / n).read_text(encoding="utf-8") != expected[n]]


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=MODELS_DIR,
                        help="folder to write the OBJ files to (default: %(default)s)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 if the folder is not what the script makes")
    args = parser.parse_args(argv)
    if args.check:
        stale = stale_files(args.out)
        for name in stale:
            print(f"out of date: {args.out / name}", file=sys.stderr)
        return 1 if stale else 0
    for path in write_models(args.out):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
