"""Door leaves on hinges: one geometric description every format and check shares.

A door (:class:`cga.model.Door`) is an opening in a wall plus a leaf that turns about a
vertical axis at the ``hinge`` end of the opening (docs/outputs.md). :func:`door_leaf` derives
the leaf's hinge frame from the plan; everything else reads it:

* the meshing poses the door model in that frame at the build's angle
  (:func:`cga.meshing.doors.leaf_node`), so glTF, plan views and renders show the state;
* the robot exports make the leaf a body on a revolute joint at :attr:`DoorLeaf.hinge`
  (axis :attr:`DoorLeaf.axis`, limits ``0`` to :attr:`DoorLeaf.upper`) that collides
  through the one box :meth:`DoorLeaf.box` in every format;
* the occupancy maps draw that box at the build's angle, so a closed door blocks a map.

The hinge frame
---------------
Origin at the hinge jamb, on the face of the wall towards the room the leaf swings into,
at the walking surface; ``x`` runs along the closed leaf towards the latch, ``y`` is up,
``z = x × y``. The closed leaf lies behind that face (inside the opening), so turning it
by up to 180° about the hinge never sweeps through the jamb or the wall, and the
quarter circle it sweeps while opening to :data:`~cga.model.DOOR_OPEN_ANGLE` is the
swing the plans draw and the furniture keeps free
(:func:`cga.operations.furniture.clearance.door_keepouts` centres it on the same point).
The leaf is :data:`SIDE_GAP` narrower than the opening at each side (at most an eighth of
a tiny opening), so its far edge,
whose back corner sweeps out by ``√(w² + t²) − w`` (under 1 mm for a 0.9 m × 0.04 m leaf),
never touches the latch jamb.

Door models follow the shipped ``door`` model: front towards −z (the swing side), hinges
at −x, origin at the centre of the footprint on the floor; the leaf's slab is the model's
largest part. A leaf hinged at the other end is the model mirrored (a left-hand door).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from cga.model import DOOR_OPEN_ANGLE, Door, FloorPlan

__all__ = ["SIDE_GAP", "BOTTOM_GAP", "TOP_GAP", "DoorLeaf", "door_leaf",
           "leaf_model_matrix", "rotation_about_y", "slab_range"]

SIDE_GAP = 0.005
"""m: clearance between the leaf and each jamb."""

BOTTOM_GAP = 0.01
"""m: clearance under the leaf, so it never scrapes the floor."""

TOP_GAP = 0.005
"""m: clearance between the leaf and the head of the opening."""


def rotation_about_y(angle: float) -> np.ndarray:
    """3×3 right-handed rotation by ``angle`` radians about world +y."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


_CORNER_SIGNS = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
"""The 8 corners of a box about its centre, in half extents (made once, not per call)."""
_CORNER_SIGNS.setflags(write=False)


@dataclass(frozen=True)
class DoorLeaf:
    """A door leaf and its hinge, in world coordinates (metres, y up).

    ``hinge`` is the origin of the hinge frame (see the module notes) and ``along`` the
    plan direction ``(x, z)`` of its x axis with the leaf closed; ``axis`` is the world
    hinge axis, ``(0, ±1, 0)``, oriented so that a positive angle opens the leaf into
    ``swing_room``. ``size`` is the leaf's box (width along x, height, thickness), which
    sits at :meth:`box` in the hinge frame. ``angle`` is how far the build leaves it open,
    within ``lower``..``upper``.
    """

    floor: int
    door: int
    rooms: tuple[int, int]
    swing_room: int
    state: str
    angle: float
    hinge: tuple[float, float, float]
    along: tuple[float, float]
    axis: tuple[float, float, float]
    size: tuple[float, float, float]
    lower: float = 0.0
    upper: float = DOOR_OPEN_ANGLE
    gaps: tuple[float, float] = (SIDE_GAP, BOTTOM_GAP)
    """(side, bottom): where the box starts from the hinge jamb and from the floor."""

    @property
    def name(self) -> str:
        """``floor{i}_door{id}``: unique in a building."""
        return f"floor{self.floor}_door{self.door}"

    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre and full extents of the leaf's box in the hinge frame."""
        width, height, thickness = self.size
        # The swing side is the frame's −z when the axis is +y (and +z when it is −y):
        # the leaf lies behind the swing face, on the other side.
        side = 1.0 if self.axis[1] > 0 else -1.0
        centre = np.array([self.gaps[0] + width / 2, self.gaps[1] + height / 2,
                           side * thickness / 2])
        return centre, np.array(self.size, dtype=float)

    def frame(self, angle: float | None = None) -> np.ndarray:
        """4×4 world transform of the hinge frame with the leaf open by ``angle``
        (default: the build's angle)."""
        turn = self.angle if angle is None else angle
        # columns x = (ax, 0, az), y = (0, 1, 0) and z = x × y, whose components are
        # written as np.cross works them out (a1·b2 − a2·b1, ...), zeros and all, so the
        # signs of zero are its signs too; np.cross costs more than the rest of the frame
        ax, az = self.along
        closed = np.array([[ax, 0.0, 0.0 * 0.0 - az * 1.0],
                           [0.0, 1.0, az * 0.0 - ax * 0.0],
                           [az, 0.0, ax * 1.0 - 0.0 * 0.0]])
        matrix = np.eye(4)
        matrix[:3, :3] = rotation_about_y(turn * self.axis[1]) @ closed
        matrix[:3, 3] = self.hinge
        return matrix

    def corners(self, angle: float | None = None) -> np.ndarray:
        """The 8 world corners of the leaf's box open by ``angle``."""
        centre, extents = self.box()
        local = centre + _CORNER_SIGNS * extents / 2
        matrix = self.frame(angle)
        return local @ matrix[:3, :3].T + matrix[:3, 3]

    def footprint(self, angle: float | None = None) -> Any:
        """The leaf's shadow in plan ``(x, z)`` (a shapely polygon)."""
        from shapely.geometry import MultiPoint

        return MultiPoint(self.corners(angle)[:, [0, 2]]).convex_hull

    def labels(self) -> dict[str, Any]:
        """The door's facts as JSON values (glTF extras, scene JSON)."""
        return {"door": self.door, "state": self.state, "angle": self.angle,
                "lower": self.lower, "upper": self.upper, "hinge": list(self.hinge),
                "axis": list(self.axis), "leaf_size": list(self.size),
                "swing_room": self.swing_room}


def door_leaf(plan: FloorPlan, door: Door, thickness: float) -> DoorLeaf:
    """The leaf of ``door`` on floor ``plan``, ``thickness`` metres thick.

    Raises
    ------
    ValueError
        The opening is too small for a leaf (narrower or lower than its gaps), or the
        thickness is not positive.
    """
    from cga.operations.furniture.clearance import face_offset

    # gaps no larger than an eighth of the opening, so a tiny door still has a leaf
    side = min(SIDE_GAP, door.width / 8)
    bottom, top = min(BOTTOM_GAP, door.height / 8), min(TOP_GAP, door.height / 8)
    width = door.width - 2 * side
    height = door.height - bottom - top
    if not (width > 0 and height > 0 and thickness > 0):
        raise ValueError(f"door {door.id} on floor {plan.index}: a {door.width:.3f} m × "
                         f"{door.height:.3f} m opening takes no {thickness:.3f} m leaf")
    wall = plan.wall(door.wall)
    # plan vectors as plain floats, worked out component by component as the vector
    # formulas (face = position + normal · offset, hinge = face − along · width / 2) do
    ux, uz = wall.unit()
    ax, az = (ux, uz) if door.hinge == "start" else (-ux, -uz)
    nx, nz = (float(v) for v in wall.normal_into(door.swing_room))
    offset = face_offset(plan, door.swing_room, door.position)
    fx, fz = door.position[0] + nx * offset, door.position[1] + nz * offset
    hx, hz = fx - ax * door.width / 2, fz - az * door.width / 2
    # the axis whose positive turn takes `along` towards `normal` is along × normal
    # (both horizontal, so it is vertical)
    axis_y = float(np.sign(az * nx - ax * nz))
    return DoorLeaf(
        floor=plan.index, door=door.id, rooms=door.rooms, swing_room=door.swing_room,
        state=door.state, angle=float(door.angle),
        hinge=(float(hx), float(plan.floor_y), float(hz)),
        along=(float(ax), float(az)), axis=(0.0, axis_y, 0.0),
        size=(float(width), float(height), float(thickness)), gaps=(side, bottom))


def leaf_model_matrix(leaf: DoorLeaf, bounds: np.ndarray, slab_z: tuple[float, float]
                      ) -> np.ndarray:
    """4×4 matrix taking a door model's frame into the hinge frame: its x extent onto the
    leaf's width (hinges at −x to the hinge side), its y extent onto the leaf's height, and
    its slab (``slab_z``, the z range of its largest part) onto the leaf's box, front (−z)
    on the swing face; handles keep their depth."""
    centre, extents = leaf.box()
    (x0, y0, _), (x1, y1, _) = bounds
    side = 1.0 if leaf.axis[1] > 0 else -1.0
    matrix = np.eye(4)
    matrix[0, 0] = extents[0] / (x1 - x0)
    matrix[1, 1] = extents[1] / (y1 - y0)
    matrix[2, 2] = side
    matrix[:3, 3] = (centre[0] - extents[0] / 2 - x0 * matrix[0, 0],
                     centre[1] - extents[1] / 2 - y0 * matrix[1, 1],
                     -side * slab_z[0])
    return matrix


def slab_range(parts: Sequence[np.ndarray]) -> tuple[float, float]:
    """The z range of a door model's slab: its largest part by box volume, given each
    part's vertices (``float[n, 3]``)."""
    boxes = [np.ptp(p, axis=0) for p in parts]
    slab = parts[int(np.argmax([float(np.prod(b)) for b in boxes]))]
    return (float(slab[:, 2].min()), float(slab[:, 2].max()))

