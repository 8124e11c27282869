"""USD output for Isaac Sim / Isaac Lab and other OpenUSD tools, ``<name>.usdc``.

The robot world (:mod:`cga.export.world`) as a stage (pxr from ``usd-core``), metres
(``metersPerUnit = 1``), ``Z`` up (robotics; ``up="Y"`` gives a Y-up stage whose
``/World/building`` is turned by −90° about x, so the content is the same):

* ``/World/Looks``: one ``UsdPreviewSurface`` material per material of the build (the
  glb's, :mod:`cga.appearance`: linear colour, roughness, metallic, opacity);
* ``/World/building/<link>``: an ``Xform`` per link at its pose (one per storey's
  structure, door leaf and item), holding its visual ``Mesh`` es (normals, bound material;
  one per structure node) and its colliders (``Cube`` or convex ``Mesh`` with
  ``UsdPhysics.CollisionAPI``, purpose ``guide`` so they do not render): the same
  convex pieces and boxes every robot format uses;
* door leaves and movable items carry ``UsdPhysics.RigidBodyAPI`` and ``MassAPI``
  (mass, centre of mass, diagonal inertia); each door has a ``PhysicsRevoluteJoint``
  (``/World/building/<door>_hinge``) to the world at its hinge, axis and limits in
  degrees, the leaf standing at the build's angle (``cga:doorState``,
  ``cga:doorAngle`` record it);
* every door and item prim, and every structure node's mesh, carries a semantic class
  label (``UsdSemantics.LabelsAPI``, taxonomy ``class``: ``wall``, ``slab``, ``door``,
  the model name, ...) and its scene node path (``cga:node``);
* ``/World/building/lights``: each room's ceiling lights as ``UsdLux.SphereLight`` s
  (5 cm radius, the light's candela as luminance over its projected area, its colour
  temperature; :mod:`cga.appearance.lights`);
* ``/World/physicsScene``: gravity along −up.

The stage passes ``UsdUtils.ComplianceChecker`` without errors (tested).
"""

from __future__ import annotations

import math
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from cga.appearance.lights import Light
from cga.appearance.material import Material
from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.scene import Scene, SceneNode

from .frames import world_to_ros
from .obj import MeshGroup
from .world import ROOT, Joint, Link, World, identifier, robot_world

__all__ = ["USD_EXTRA", "world_as_stage", "export_usd"]

USD_EXTRA = "usd-core"
"""The package that provides ``pxr`` (in the ``robot`` extra: ``pip install cga[robot]``)."""


def _pxr() -> Any:
    try:
        import pxr  # noqa: F401
        from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdSemantics, UsdShade, Vt
    except ImportError:
        raise ExportError("the USD export needs the usd-core package: "
                          "pip install 'cga[robot]' (or pip install usd-core)") from None
    return Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdSemantics, UsdShade, Vt


class _StageWriter:
    """Writes one world into a fresh in-memory stage."""

    def __init__(self, world: World, up: Literal["Z", "Y"]):
        (self.Gf, self.Sdf, self.Usd, self.UsdGeom, self.UsdPhysics, self.UsdSemantics,
         self.UsdShade, self.Vt) = _pxr()
        self.world = world
        self.stage = self.Usd.Stage.CreateInMemory()
        UsdGeom = self.UsdGeom
        UsdGeom.SetStageUpAxis(self.stage, UsdGeom.Tokens.z if up == "Z" else UsdGeom.Tokens.y)
        UsdGeom.SetStageMetersPerUnit(self.stage, 1.0)
        root = UsdGeom.Xform.Define(self.stage, "/World")
        self.stage.SetDefaultPrim(root.GetPrim())
        self.materials = self._materials()
        building = UsdGeom.Xform.Define(self.stage, f"/World/{ROOT}")
        # the building's frame in the stage: ROS (x, y, z) → y-up (x, z, −y) is −90°
        # about x
        turn = -math.pi / 4 if up == "Y" else 0.0
        self.up = self.Gf.Quatf(math.cos(turn), math.sin(turn), 0.0, 0.0)
        if up == "Y":
            building.AddRotateXOp().Set(-90.0)
        scene = self.UsdPhysics.Scene.Define(self.stage, "/World/physicsScene")
        scene.CreateGravityDirectionAttr(self.Gf.Vec3f(0, 0, -1) if up == "Z"
                                         else self.Gf.Vec3f(0, -1, 0))
        scene.CreateGravityMagnitudeAttr(9.81)

    def _materials(self) -> dict[str, Any]:
        out = {}
        self.UsdGeom.Scope.Define(self.stage, "/World/Looks")
        collision = Material.of("collision", "collision", (0.9, 0.3, 0.3), 0.8, 0.0, 1.0)
        for name, look in sorted({**self.world.materials, "collision": collision}.items()):
            material = self.UsdShade.Material.Define(self.stage, f"/World/Looks/{name}")
            shader = self.UsdShade.Shader.Define(self.stage, f"/World/Looks/{name}/surface")
            shader.CreateIdAttr("UsdPreviewSurface")
            # UsdPreviewSurface colours are linear, like glTF's
            shader.CreateInput("diffuseColor", self.Sdf.ValueTypeNames.Color3f).Set(
                self.Gf.Vec3f(*look.linear_rgba()[:3]))
            shader.CreateInput("roughness", self.Sdf.ValueTypeNames.Float).Set(look.roughness)
            shader.CreateInput("metallic", self.Sdf.ValueTypeNames.Float).Set(look.metallic)
            if look.transparent:
                shader.CreateInput("opacity", self.Sdf.ValueTypeNames.Float).Set(look.alpha)
            material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
            out[name] = material
        return out

    def _mesh(self, path: str, group: MeshGroup, *, guide: bool) -> Any:
        vertices = np.asarray(group.vertices, dtype=float)
        faces = np.asarray(group.faces, dtype=np.int64)
        mesh = self.UsdGeom.Mesh.Define(self.stage, path)
        mesh.CreatePointsAttr(self.Vt.Vec3fArray.FromNumpy(vertices.astype(np.float32)))
        mesh.CreateFaceVertexCountsAttr(self.Vt.IntArray.FromNumpy(
            np.full(len(faces), 3, dtype=np.int32)))
        mesh.CreateFaceVertexIndicesAttr(self.Vt.IntArray.FromNumpy(
            faces.ravel().astype(np.int32)))
        a, b, c = (vertices[faces[:, i]] for i in range(3))
        normals = np.cross(b - a, c - a)
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
        mesh.CreateNormalsAttr(self.Vt.Vec3fArray.FromNumpy(
            np.repeat(normals, 3, axis=0).astype(np.float32)))
        mesh.SetNormalsInterpolation(self.UsdGeom.Tokens.faceVarying)
        mesh.CreateSubdivisionSchemeAttr(self.UsdGeom.Tokens.none)
        mesh.CreateExtentAttr(self.Vt.Vec3fArray.FromNumpy(
            np.array([vertices.min(axis=0), vertices.max(axis=0)], dtype=np.float32)))
        if guide:
            mesh.CreatePurposeAttr(self.UsdGeom.Tokens.guide)
        self._bind(mesh.GetPrim(), "collision" if guide else group.material)
        return mesh

    def _bind(self, prim: Any, material: str) -> None:
        self.UsdShade.MaterialBindingAPI.Apply(prim).Bind(self.materials[material])

    def _placed(self, path: str, position: Sequence[float], yaw: float) -> Any:
        xform = self.UsdGeom.Xform.Define(self.stage, path)
        xform.AddTranslateOp().Set(self.Gf.Vec3d(*position))
        xform.AddRotateZOp().Set(math.degrees(yaw))
        return xform

    def link(self, link: Link) -> None:
        path = f"/World/{ROOT}/{link.name}"
        joint = None if link.role == "structure" else self.world.joint_of(link.name)
        yaw = link.pose.yaw + (joint.axis[2] * joint.position if joint and joint.kind == "revolute"
                               else 0.0)
        prim = self._placed(path, link.pose.position, yaw).GetPrim()
        if link.node is not None:
            self._label(prim, link.label, link.node)
        for k, group in enumerate(link.visual):
            mesh = self._mesh(f"{path}/visual{k}", group, guide=False).GetPrim()
            if link.role == "structure":  # one mesh per structure node: label it
                self._label(mesh, group.material, group.name)
        for collider in link.colliders:
            self._collider(f"{path}/{collider.name}", collider)
        if link.movable:
            self.UsdPhysics.RigidBodyAPI.Apply(prim)
            mass = self.UsdPhysics.MassAPI.Apply(prim)
            mass.CreateMassAttr(link.mass)
            mass.CreateCenterOfMassAttr(self.Gf.Vec3f(*link.com))
            mass.CreateDiagonalInertiaAttr(self.Gf.Vec3f(*np.maximum(link.inertia, 1e-9)))
            mass.CreatePrincipalAxesAttr(self.Gf.Quatf(1.0, 0.0, 0.0, 0.0))
        if joint is not None and joint.kind == "revolute":
            self._hinge(link, joint)

    def _label(self, prim: Any, label: str, node: str) -> None:
        """The prim's semantic class and the path of the scene node it shows."""
        self.UsdSemantics.LabelsAPI.Apply(prim, "class").CreateLabelsAttr([label])
        prim.CreateAttribute("cga:node", self.Sdf.ValueTypeNames.String).Set(node)

    def _collider(self, path: str, collider: Any) -> None:
        if collider.box is not None:
            cube = self.UsdGeom.Cube.Define(self.stage, path)
            cube.CreateSizeAttr(1.0)
            cube.AddTranslateOp().Set(self.Gf.Vec3d(*collider.box.centre))
            cube.AddRotateZOp().Set(math.degrees(collider.box.yaw))
            cube.AddScaleOp().Set(self.Gf.Vec3f(*collider.box.extents))
            cube.CreatePurposeAttr(self.UsdGeom.Tokens.guide)
            self._bind(cube.GetPrim(), "collision")
            self.UsdPhysics.CollisionAPI.Apply(cube.GetPrim())
            return
        mesh = self._mesh(path, collider.mesh, guide=True)
        self.UsdPhysics.CollisionAPI.Apply(mesh.GetPrim())
        self.UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr(
            self.UsdPhysics.Tokens.convexHull)

    def _hinge(self, link: Link, joint: Joint) -> None:
        hinge = self.UsdPhysics.RevoluteJoint.Define(self.stage, f"/World/{ROOT}/{joint.name}")
        # body0 unset: the joint holds the leaf to the world (stage frame), at the closed
        # leaf's frame
        hinge.CreateBody1Rel().SetTargets([f"/World/{ROOT}/{link.name}"])
        position = self.up.Transform(self.Gf.Vec3f(*link.pose.position))
        hinge.CreateLocalPos0Attr(position)
        half = link.pose.yaw / 2
        hinge.CreateLocalRot0Attr(self.up * self.Gf.Quatf(math.cos(half), 0.0, 0.0,
                                                           math.sin(half)))
        hinge.CreateLocalPos1Attr(self.Gf.Vec3f(0.0, 0.0, 0.0))
        hinge.CreateLocalRot1Attr(self.Gf.Quatf(1.0, 0.0, 0.0, 0.0))
        # axis Z of the joint frame; a door whose opening turns about −z has its limits
        # negated (the joint's positive sense is +z)
        hinge.CreateAxisAttr("Z")
        low, high = (math.degrees(joint.lower), math.degrees(joint.upper))
        if joint.axis[2] < 0:
            low, high = -high, -low
        hinge.CreateLowerLimitAttr(low)
        hinge.CreateUpperLimitAttr(high)
        prim = hinge.GetPrim()
        prim.CreateAttribute("cga:doorState", self.Sdf.ValueTypeNames.String).Set(joint.state or "")
        prim.CreateAttribute("cga:doorAngle", self.Sdf.ValueTypeNames.Float).Set(
            math.degrees(joint.position))


    def lights(self, lights: Sequence[Light]) -> None:
        """Each ceiling light as a small ``UsdLux.SphereLight`` under
        ``/World/building/lights`` (ROS frame, like the links): its luminance is the
        light's candela over the sphere's projected area, its colour its temperature."""
        from pxr import UsdLux

        if not lights:
            return
        self.UsdGeom.Scope.Define(self.stage, f"/World/{ROOT}/lights")
        area = math.pi * _LIGHT_RADIUS ** 2
        for light in lights:
            path = f"/World/{ROOT}/lights/{identifier(light.name)}"
            sphere = UsdLux.SphereLight.Define(self.stage, path)
            sphere.AddTranslateOp().Set(self.Gf.Vec3d(*(float(v) for v in
                                                          world_to_ros(light.position))))
            sphere.CreateRadiusAttr(_LIGHT_RADIUS)
            sphere.CreateIntensityAttr(light.intensity / area)
            sphere.CreateEnableColorTemperatureAttr(True)
            sphere.CreateColorTemperatureAttr(light.temperature)
            sphere.GetPrim().CreateAttribute("cga:node", self.Sdf.ValueTypeNames.String).Set(
                light.name)


_LIGHT_RADIUS = 0.05
"""Radius (m) of the sphere lights standing for the ceiling lights."""


def world_as_stage(world: World, *, up: Literal["Z", "Y"] = "Z",
                   lights: Sequence[Light] = ()) -> Any:
    """The world as an in-memory ``pxr.Usd.Stage`` (see the module notes), with the
    build's ceiling ``lights``.

    Raises
    ------
    ExportError
        ``usd-core`` is not installed.
    """
    writer = _StageWriter(world, up)
    for link in world.links:
        if link.name != ROOT:
            writer.link(link)
    writer.lights(lights)
    return writer.stage


def export_usd(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str, *,
               up: Literal["Z", "Y"] = "Z") -> list[Path]:
    """Write ``<name>.usdc`` (binary USD; ``up`` axis ``Z``, ``cga build``'s choice, or
    ``Y``).

    Raises
    ------
    ExportError
        ``usd-core`` is not installed, or see :func:`cga.export.world.robot_world`.
    """
    _pxr()
    stage = world_as_stage(robot_world(scene, nodes), up=up, lights=scene.lights)
    with tempfile.TemporaryDirectory(prefix="cga-usd-") as folder:
        temporary = Path(folder) / f"{name}.usdc"
        if not stage.GetRootLayer().Export(os.fspath(temporary)):
            raise ExportError(f"usd-core could not write {name}.usdc")
        data = temporary.read_bytes()
    return [atomic_write(Path(out_dir) / f"{name}.usdc", data)]
