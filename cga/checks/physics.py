"""Physics check: does the furniture rest where it was put, without overlapping anything?

A generated world is only useful to a robot simulator if it is at rest when the
simulation starts: an item sunk into a wall is flung across the room on the first step,
an item placed in mid-air falls. This check loads a scene into pybullet (DIRECT mode, its
own server), measures how deeply each item overlaps the structure or another item, lets
gravity act for a short while and measures how far each item moved and turned
(docs/checks.md).

Frame: the world frame is used as is (metres, y up) with gravity along −y, so positions
in the report need no conversion. Structure (walls, slabs, ceilings) is static: each
node is cut into convex pieces along axis-aligned planes through its vertices (a wall
with openings becomes boxes), and kept as one concave triangle mesh when it does not cut
into convex pieces. Boxes rather than triangle meshes, because Bullet's contacts between
a convex part and the long thin triangles of a slab triangulated around T-junctions push
sideways: standing on the slab as one mesh, a washbasin tipped over and wardrobes walked
2–3 cm in 5 of 200 house seeds. Each piece is a body of its own rather than a child of
one compound per node: with compounds the check's verdicts on the demo buildings were
the same, but the items took longer to come to rest (a fifth to a third more simulated
time), which cost back what the fewer bodies saved. Each solid item is one rigid body (maximal
coordinates, like the static pieces: a plain rigid body's contacts cost less to solve
than those of a one-link multibody, pybullet's default) whose collision shape is a
compound of its convex parts (V-HACD pieces for models that are not made of convex
parts, see :mod:`cga.checks.vhacd`), with the item's mass at the parts' centroid,
measured once per model (:mod:`cga.checks._item_solids`). Static
furniture (rugs, which may overlap anything, and door and window details, which sit in
their openings) is not simulated.

Settling runs for ``settle_seconds`` of simulated time at ``timestep``, and stops early
once every item has been at rest (speed below 1 mm/s and spin below 0.01 rad/s) for
0.1 s: at those speeds an item covers less than the thresholds in what is left of the
settle time, so the early stop does not hide a failure, and a furnished house settles
in a tenth of the time. Storeys settle independently: nothing of one storey's furniture
touches another's, so each storey's items stop (their poses are taken and their bodies
leave the simulation) once that storey has rested, and the cost of a building grows with
the sum of its storeys' settling times, not with the slowest storey times them all. An item balanced so finely that it starts to tip too slowly to
notice in that time is caught statically: its centre of mass must lie over the hull of
the points it stands on (its vertices within 5 mm of its lowest point).
"""

from __future__ import annotations

import math
import os
import re
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from cga.collision import BULLET_MARGIN, CONTACT_SHRINK
from cga.scene import Scene, SceneNode

from ._boxes import box_pieces
from ._bullet import direct_client
from ._item_solids import ItemShape, item_shape, item_solid
from ._solids import convex_pieces

__all__ = [
    "DEFAULT_DENSITY",
    "TIP_ANGLE_DEG",
    "ItemPhysics",
    "PhysicsReport",
    "check_physics",
    "structure_nodes",
    "item_nodes",
]

DEFAULT_DENSITY = 500.0
"""kg/m³ used for an item whose node carries neither ``mass`` nor ``density``."""

TIP_ANGLE_DEG = 30.0
"""An item whose up axis ends more than this far from vertical has tipped over."""

GRAVITY = 9.81
"""m/s², along −y."""

_REST_SPEED = 1e-3
"""m/s: an item slower than this (and spinning slower than :data:`_REST_SPIN`) is at rest."""

_REST_SPIN = 1e-2
"""rad/s."""

_REST_SECONDS = 0.1
"""Simulated time every item must stay at rest before settling stops early."""

_CHECK_EVERY = 0.025
"""Simulated seconds between two rest checks."""

_STABILITY_TOLERANCE = 0.01
"""m: an item whose centre of mass lies further than this outside the hull of the points
it stands on is about to tip."""

_MARGIN = BULLET_MARGIN
_SHRINK = CONTACT_SHRINK
"""With the margin added back, an item's surface lies 1 mm inside its true one while the
structure's lies 1 mm outside, so an item standing on the floor or flush against a wall
touches it exactly, and two items placed side by side keep a 2 mm gap
(:mod:`cga.collision`)."""

_INFLATION = {"item": _MARGIN - _SHRINK, "static": _MARGIN}
"""How far each kind of body's collision surface lies outside its true surface (m); a
reported distance minus both inflations is the true distance."""

_OVERLAP_EPS = 1e-4
"""m: overlaps shallower than this (numerical noise of touching shapes) count as touching."""

_SUPPORT_TOLERANCE = 0.05
"""m: an item whose top ends this far below the surface it stood over fell through it."""


@dataclass(frozen=True)
class ItemPhysics:
    """The physics result of one furniture item (lengths in metres, angles in degrees).

    ``penetration`` is the deepest initial overlap with the structure or another item
    (0 when it only touches), ``penetrating`` the path of the node it overlaps most.
    ``displacement`` and ``rotation_deg`` compare the pose after settling with the pose
    before. ``fell_through``: the item ended below the surface it stood over (or, with
    nothing under it, below its starting height). ``tipped``: its up axis ended more than
    :data:`TIP_ANGLE_DEG` from vertical. ``stable``: its centre of mass lies over the
    hull of the points it stands on. ``problems`` says in words what failed.
    """

    path: str
    name: str
    model: str
    room: int | None
    mass: float
    penetration: float
    penetrating: str | None
    displacement: float
    rotation_deg: float
    fell_through: bool
    tipped: bool
    stable: bool = True
    problems: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        return not self.problems

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (lengths in metres, rounded to 0.1 mm)."""
        return {
            "path": self.path,
            "name": self.name,
            "model": self.model,
            "room": self.room,
            "mass_kg": round(self.mass, 3),
            "penetration_m": round(self.penetration, 4),
            "penetrating": self.penetrating,
            "displacement_m": round(self.displacement, 4),
            "rotation_deg": round(self.rotation_deg, 3),
            "fell_through": self.fell_through,
            "tipped": self.tipped,
            "stable": self.stable,
            "passed": self.passed,
            "problems": list(self.problems),
        }


@dataclass(frozen=True)
class PhysicsReport:
    """The result of :func:`check_physics`: one :class:`ItemPhysics` per simulated item.

    ``ignored`` lists the static furniture nodes that were not simulated (rugs, door and
    window details). ``simulated_seconds`` may be less than ``settle_seconds`` when every
    item came to rest early. ``elapsed_seconds`` is wall-clock time of the whole check; it
    is left out of :meth:`to_dict`, so two builds with one seed give the same report.
    """

    items: tuple[ItemPhysics, ...]
    penetration_tol: float
    move_tol: float
    rot_tol_deg: float
    settle_seconds: float
    simulated_seconds: float
    timestep: float
    elapsed_seconds: float
    ignored: tuple[str, ...] = ()
    structure_count: int = 0

    @property
    def passed(self) -> bool:
        return all(item.passed for item in self.items)

    @property
    def failures(self) -> list[ItemPhysics]:
        """The items that failed, in scene order."""
        return [item for item in self.items if not item.passed]

    @property
    def max_penetration(self) -> float:
        return max((i.penetration for i in self.items), default=0.0)

    @property
    def max_displacement(self) -> float:
        return max((i.displacement for i in self.items), default=0.0)

    def summary(self) -> str:
        """One line for the terminal, e.g. ``physics: 58/60 items at rest; ...``."""
        ok = len(self.items) - len(self.failures)
        text = (f"physics: {ok}/{len(self.items)} items at rest "
                f"(max penetration {self.max_penetration * 1000:.1f} mm, "
                f"max displacement {self.max_displacement * 100:.1f} cm)")
        if self.failures:
            text += "; " + "; ".join(f"{i.path}: {', '.join(i.problems)}" for i in self.failures)
        return text

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form for the scene file (``checks.physics``); deterministic."""
        return {
            "passed": self.passed,
            "thresholds": {
                "penetration_m": self.penetration_tol,
                "displacement_m": self.move_tol,
                "rotation_deg": self.rot_tol_deg,
            },
            "settle_seconds": self.settle_seconds,
            "simulated_seconds": round(self.simulated_seconds, 4),
            "timestep": self.timestep,
            "item_count": len(self.items),
            "failed_count": len(self.failures),
            "max_penetration_m": round(self.max_penetration, 4),
            "max_displacement_m": round(self.max_displacement, 4),
            "items": [item.to_dict() for item in self.items],
            "ignored": list(self.ignored),
        }


def structure_nodes(nodes: Sequence[SceneNode]) -> list[SceneNode]:
    """The static building structure: every static node that is not furniture."""
    return [n for n in nodes if n.static and n.kind != "furniture"]


def item_nodes(nodes: Sequence[SceneNode]) -> list[SceneNode]:
    """The solid furniture items: furniture nodes that are not static."""
    return [n for n in nodes if n.kind == "furniture" and not n.static]


def check_physics(scene: Scene, nodes: Sequence[SceneNode] | None = None, *,
                  settle_seconds: float = 2.0, penetration_tol: float = 0.005,
                  move_tol: float = 0.01, rot_tol_deg: float = 2.0,
                  timestep: float = 1.0 / 240.0,
                  cache_dir: Path | None = None) -> PhysicsReport:
    """Simulate the scene's furniture under gravity and report overlaps and motion.

    Parameters
    ----------
    scene
        The built scene.
    nodes
        The nodes to check (world-space meshes); default ``scene.nodes``, the build's
        own meshes (made once per scene).
    settle_seconds
        Simulated time to let the items settle (stops early once all rest).
    penetration_tol, move_tol, rot_tol_deg
        Pass thresholds: initial overlap (m), displacement (m), rotation (degrees).
    timestep
        Simulation step (s).
    cache_dir
        Folder of cached V-HACD decompositions (default :func:`cga.checks.vhacd.cache_dir`).

    Returns
    -------
    PhysicsReport
        Per-item results; ``passed`` when no item overlaps by more than
        ``penetration_tol`` or moves more than ``move_tol`` or ``rot_tol_deg``, and
        none fell through the floor or tipped over.

    Raises
    ------
    ValueError
        A threshold or time is not positive, or a furniture node has no geometry.

    Notes
    -----
    Cost is dominated by the simulation: about (items × settled steps) convex-vs-mesh
    contact tests. Overlap is measured with ``getClosestPoints`` before any step, between
    each item and every body whose bounding box meets its own; the
    collision margins pybullet adds around shapes (1 mm) and the 2 mm by which item parts
    are shrunk are accounted for, so an item standing on the floor or flush against a
    wall has penetration 0.
    """
    for label, value in (("settle_seconds", settle_seconds), ("timestep", timestep),
                         ("penetration_tol", penetration_tol), ("move_tol", move_tol),
                         ("rot_tol_deg", rot_tol_deg)):
        if not value > 0:
            raise ValueError(f"check_physics: {label} must be positive, got {value!r}")
    started = time.perf_counter()
    if nodes is None:
        nodes = scene.nodes
    structure = [n for n in structure_nodes(nodes) if len(n.mesh.faces)]
    items = item_nodes(nodes)
    for node in items:
        if len(node.mesh.faces) == 0:
            raise ValueError(f"furniture node {node.path} has no geometry")
    ignored = tuple(n.path for n in nodes if n.kind == "furniture" and n.static)
    with direct_client() as (pb, client), tempfile.TemporaryDirectory(prefix="cga-physics-") as tmp:
        world = _World(pb, client, Path(tmp), timestep)
        for node in structure:
            world.add_static(node)
        supports = world.support_heights([_centroid(n) for n in items])
        bodies = [world.add_item(n, cache_dir) for n in items]
        depths = world.penetrations(bodies)
        simulated = world.settle(bodies, settle_seconds)
        results = []
        for node, body, support, (depth, other) in zip(items, bodies, supports, depths):
            results.append(_item_result(node, body, world, support, depth, other,
                                        penetration_tol, move_tol, rot_tol_deg))
    return PhysicsReport(
        items=tuple(results),
        penetration_tol=penetration_tol,
        move_tol=move_tol,
        rot_tol_deg=rot_tol_deg,
        settle_seconds=settle_seconds,
        simulated_seconds=simulated,
        timestep=timestep,
        elapsed_seconds=time.perf_counter() - started,
        ignored=ignored,
        structure_count=len(structure),
    )


_STOREY = re.compile(r"^floor(\d+)/")
"""The storey of a node from its path (``floor1/room3_Kitchen/furniture/sofa``)."""

_Pose = tuple[np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]
"""Position, quaternion (x, y, z, w) and bounding box of a body."""


@dataclass
class _Body:
    """A dynamic item in the simulation: body id, mass, starting centre of mass, lowest
    point, how far its centre of mass lies outside what it stands on, and its pose once
    its storey has settled."""

    uid: int
    mass: float
    start: np.ndarray
    bottom: float
    path: str
    support_gap: float
    final: _Pose | None = None

    @property
    def storey(self) -> int | None:
        match = _STOREY.match(self.path)
        return int(match.group(1)) if match else None


@dataclass
class _World:
    """A pybullet DIRECT server holding one scene, with gravity along −y."""

    pb: Any
    client: int
    folder: Path
    timestep: float
    paths: dict[int, str] = field(default_factory=dict)
    kinds: dict[int, str] = field(default_factory=dict)
    shapes: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.pb.setGravity(0.0, -GRAVITY, 0.0, physicsClientId=self.client)
        self.pb.setPhysicsEngineParameter(fixedTimeStep=self.timestep,
                                          deterministicOverlappingPairs=1,
                                          physicsClientId=self.client)

    def add_static(self, node: SceneNode) -> None:
        """Static bodies for a structure node: its convex pieces when it cuts into them
        (:func:`box_pieces` for a rectilinear solid, else :func:`convex_pieces`), else
        the node as one concave triangle mesh."""
        pieces = box_pieces(node.mesh)
        if pieces is None:
            pieces = convex_pieces(node.mesh)
        if pieces is None:
            mesh = node.mesh
            shape = self.pb.createCollisionShape(
                self.pb.GEOM_MESH, vertices=np.asarray(mesh.vertices, dtype=float).tolist(),
                indices=np.asarray(mesh.faces, dtype=int).ravel().tolist(),
                flags=self.pb.GEOM_FORCE_CONCAVE_TRIMESH, physicsClientId=self.client)
            shapes = [shape]
        else:
            shapes = [self.pb.createCollisionShape(
                self.pb.GEOM_MESH, vertices=np.asarray(piece.vertices, dtype=float).tolist(),
                physicsClientId=self.client) for piece in pieces]
        for shape in shapes:
            if shape < 0:
                raise RuntimeError(f"pybullet rejected the mesh of {node.path}")
            uid = self.pb.createMultiBody(0.0, shape, useMaximalCoordinates=True,
                                          physicsClientId=self.client)
            self.paths[uid], self.kinds[uid] = node.path, "static"

    def add_item(self, node: SceneNode, cache_dir: Path | None) -> _Body:
        """A dynamic compound body for a furniture item, its origin at the parts' centre of
        mass; items of one model, size and turn share one collision shape."""
        solid, linear, offset = item_solid(node, cache_dir)
        centroid = linear @ solid.centroid + offset
        shape = item_shape(solid, linear)
        mass = _mass(node, solid.volume * abs(float(np.linalg.det(linear))))
        uid = self.pb.createMultiBody(mass, self._shape(shape, node.path),
                                      basePosition=centroid.tolist(),
                                      useMaximalCoordinates=True, physicsClientId=self.client)
        self.pb.changeDynamics(uid, -1, restitution=0.0, physicsClientId=self.client)
        self.paths[uid], self.kinds[uid] = node.path, "item"
        return _Body(uid=uid, mass=mass, start=centroid, bottom=float(centroid[1] + shape.lowest),
                     path=node.path, support_gap=shape.support_gap)

    def _shape(self, shape: ItemShape, path: str) -> int:
        """The pybullet collision shape of ``shape``, made on its first use in this world."""
        uid = self.shapes.get(shape.name)
        if uid is None:
            file = self.folder / f"{shape.name}.obj"
            file.write_text(shape.text, encoding="utf-8")
            uid = self.pb.createCollisionShape(self.pb.GEOM_MESH, fileName=os.fspath(file),
                                               physicsClientId=self.client)
            if uid < 0:
                raise RuntimeError(f"pybullet rejected the convex parts of {path}")
            self.shapes[shape.name] = uid
        return uid

    def support_heights(self, points: Sequence[np.ndarray]) -> list[float | None]:
        """For each point, the height of the first static surface straight below it."""
        if not points:
            return []
        starts = [p.tolist() for p in points]
        ends = [[p[0], p[1] - 1000.0, p[2]] for p in points]
        heights: list[float | None] = []
        batch = self.pb.MAX_RAY_INTERSECTION_BATCH_SIZE
        for i in range(0, len(starts), batch):
            hits = self.pb.rayTestBatch(starts[i:i + batch], ends[i:i + batch],
                                        physicsClientId=self.client)
            heights.extend(None if hit[0] < 0 else float(hit[3][1]) for hit in hits)
        return heights

    def penetrations(self, bodies: Sequence[_Body]) -> list[tuple[float, str | None]]:
        """Deepest initial overlap of each body with any other body, and with which."""
        self.pb.performCollisionDetection(physicsClientId=self.client)
        out = []
        for body in bodies:
            lo, hi = self.pb.getAABB(body.uid, -1, physicsClientId=self.client)
            near = self.pb.getOverlappingObjects(lo, hi, physicsClientId=self.client) or []
            deepest, which = 0.0, None
            for other in sorted({uid for uid, _ in near if uid != body.uid}):
                points = self.pb.getClosestPoints(body.uid, other, 2 * _SHRINK,
                                                  physicsClientId=self.client)
                if not points:
                    continue
                true_distance = (min(p[8] for p in points) + _INFLATION["item"]
                                 + _INFLATION[self.kinds[other]])
                depth = -true_distance
                if depth > max(deepest, _OVERLAP_EPS):
                    deepest, which = depth, self.paths[other]
            out.append((deepest, which))
        return out

    def settle(self, bodies: Sequence[_Body], seconds: float) -> float:
        """Step until ``seconds`` have passed or every storey's bodies have rested for a
        while; returns the simulated time (of the last storey to rest).

        A storey that has rested is done: its bodies' poses are kept in ``body.final``
        and the bodies are removed, so later steps simulate only the storeys still
        moving. Every body has ``final`` set on return."""
        steps = max(1, round(seconds / self.timestep))
        check = max(1, round(_CHECK_EVERY / self.timestep))
        needed = max(1, math.ceil(_REST_SECONDS / (check * self.timestep)))
        groups: dict[int | None, list[_Body]] = {}
        for body in bodies:
            groups.setdefault(body.storey, []).append(body)
        resting = dict.fromkeys(groups, 0)
        for step in range(1, steps + 1):
            self.pb.stepSimulation(physicsClientId=self.client)
            if step % check:
                continue
            for storey, group in list(groups.items()):
                resting[storey] = resting[storey] + 1 if self._all_resting(group) else 0
                if resting[storey] >= needed:
                    self._retire(groups.pop(storey))
            if not groups:
                return step * self.timestep
        for group in groups.values():
            self._retire(group)
        return steps * self.timestep

    def _retire(self, group: Sequence[_Body]) -> None:
        """Keep the bodies' poses and take them out of the simulation."""
        for body in group:
            body.final = self.pose(body)
        for body in group:
            self.pb.removeBody(body.uid, physicsClientId=self.client)

    def _all_resting(self, bodies: Sequence[_Body]) -> bool:
        for body in bodies:
            linear, angular = self.pb.getBaseVelocity(body.uid, physicsClientId=self.client)
            if np.linalg.norm(linear) > _REST_SPEED or np.linalg.norm(angular) > _REST_SPIN:
                return False
        return True

    def pose(self, body: _Body) -> _Pose:
        """Position, quaternion (x, y, z, w) and bounding box of a body now."""
        position, orientation = self.pb.getBasePositionAndOrientation(
            body.uid, physicsClientId=self.client)
        lo, hi = self.pb.getAABB(body.uid, -1, physicsClientId=self.client)
        return np.asarray(position), np.asarray(orientation), (np.asarray(lo), np.asarray(hi))


def _centroid(node: SceneNode) -> np.ndarray:
    """The centre of an item's bounding box (from its parts, the same vertices as its
    mesh, when it has them)."""
    if node.parts:
        vertices = np.concatenate([np.asarray(p.vertices, dtype=float) for p in node.parts])
        return (vertices.min(axis=0) + vertices.max(axis=0)) / 2
    lo, hi = node.mesh.bounds
    return (lo + hi) / 2


def _mass(node: SceneNode, volume: float) -> float:
    """The item's mass (kg): its :class:`~cga.scene.ItemInfo` mass, else density (the
    model's, or :data:`DEFAULT_DENSITY` for a node without item facts) × volume."""
    item = node.item
    if item is not None and item.mass > 0:
        return item.mass
    density = item.density if item is not None and item.density > 0 else DEFAULT_DENSITY
    return max(density * volume, 1e-3)


def _item_result(node: SceneNode, body: _Body, world: _World, support: float | None,
                 depth: float, other: str | None, penetration_tol: float, move_tol: float,
                 rot_tol_deg: float) -> ItemPhysics:
    position, quaternion, (_, top) = body.final if body.final is not None else world.pose(body)
    displacement = float(np.linalg.norm(position - body.start))
    rotation = math.degrees(2.0 * math.acos(min(1.0, abs(float(quaternion[3])))))
    up = _rotate(quaternion, np.array([0.0, 1.0, 0.0]))
    tilt = math.degrees(math.acos(max(-1.0, min(1.0, float(up[1])))))
    surface = support if support is not None else body.bottom
    fell = bool(top[1] < surface - _SUPPORT_TOLERANCE)
    tipped = tilt > TIP_ANGLE_DEG
    stable = body.support_gap <= _STABILITY_TOLERANCE
    problems = []
    if depth > penetration_tol:
        problems.append(f"overlaps {other} by {depth * 1000:.1f} mm "
                        f"(limit {penetration_tol * 1000:g} mm)")
    if fell:
        problems.append("fell through the floor" if support is not None
                        else "has no floor under it and fell")
    if tipped:
        problems.append(f"tipped over ({tilt:.0f}° from upright)")
    elif not stable and not fell:
        problems.append(f"will tip: its centre of mass is {body.support_gap * 100:.1f} cm "
                        f"outside the points it stands on")
    if displacement > move_tol:
        problems.append(f"moved {displacement * 100:.1f} cm (limit {move_tol * 100:g} cm)")
    if rotation > rot_tol_deg:
        problems.append(f"turned {rotation:.1f}° (limit {rot_tol_deg:g}°)")
    item = node.item
    return ItemPhysics(
        path=node.path,
        name=item.name if item is not None else node.path.rsplit("/", 1)[-1],
        model=item.model if item is not None else "",
        room=item.room if item is not None else None,
        mass=body.mass,
        penetration=depth,
        penetrating=other,
        displacement=displacement,
        rotation_deg=rotation,
        fell_through=fell,
        tipped=tipped,
        stable=stable,
        problems=tuple(problems),
    )


def _rotate(quaternion: np.ndarray, vector: np.ndarray) -> np.ndarray:
    """Rotate ``vector`` by the unit quaternion (x, y, z, w)."""
    q = np.asarray(quaternion[:3], dtype=float)
    w = float(quaternion[3])
    t = 2.0 * np.cross(q, vector)
    return vector + w * t + np.cross(q, t)
