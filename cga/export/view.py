"""A rendered 3D view of a build: ``<name>.view.png``, with no display and no GPU.

Robot researchers and grammar authors want a quick look at a build without opening a
viewer. This renders the scene's nodes from an elevated three-quarter view as a
"doll's house": every storey is cut at ``cut_height`` above its walking surface and
ceilings and roofs are left out, so rooms and furniture are visible from above. Triangles are
flat-shaded with one directional light and rasterised with
a small z-buffer at 2× size, then downsampled for anti-aliasing. Storeys are drawn side by side.

Both faces of every triangle are drawn (cut meshes may be open), so no back-face
culling; the z-buffer keeps the nearest. No OpenGL, no window system.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import trimesh
from PIL import Image

from cga.fsutil import atomic_write
from cga.manifold import manifold3d
from cga.mesh import as_trimesh
from cga.scene import Scene, SceneNode

from .palette import face_colors, node_color, node_face_colors

__all__ = ["render_view", "export_view"]

_LIGHT = np.array([0.45, 0.8, 0.35]) / np.linalg.norm([0.45, 0.8, 0.35])
_BACKGROUND = (250, 249, 246)


def _camera(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Rows: screen right, screen up, towards the viewer (world, y up)."""
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    to_viewer = np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    right = np.cross([0.0, 1.0, 0.0], to_viewer)
    right /= np.linalg.norm(right)
    up = np.cross(to_viewer, right)
    return np.vstack([right, up, to_viewer])


def _cut(mesh: trimesh.Trimesh, height: float
         ) -> tuple[trimesh.Trimesh, np.ndarray | None] | None:
    """The part of ``mesh`` below ``height`` (capped so walls look solid), and for each of
    its triangles the triangle of ``mesh`` it comes from (-1 for a cap; None when that is
    not known)."""
    if mesh.bounds[1][1] <= height:
        return mesh, np.arange(len(mesh.faces))
    if mesh.bounds[0][1] >= height:
        return None
    if not mesh.is_watertight:
        return mesh.slice_plane([0.0, height, 0.0], [0.0, -1.0, 0.0]), None
    solid = manifold3d.Manifold(manifold3d.Mesh(
        vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
        tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))
    cut = solid.trim_by_plane((0.0, -1.0, 0.0), -height).to_mesh()
    if len(cut.tri_verts) == 0:
        return None
    vertices = np.asarray(cut.vert_properties)[:, :3]
    faces = np.asarray(cut.tri_verts)
    # manifold gives each triangle the index of the input triangle it comes from
    # (face_id); the cap it adds lies in the cutting plane
    source = np.asarray(cut.face_id, dtype=np.int64).copy()
    source[np.all(np.abs(vertices[faces][:, :, 1] - height) < 1e-5, axis=1)] = -1
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False), source


def _storey_triangles(nodes: Sequence[SceneNode], cut_y: float | None):
    tris, colors = [], []
    for node in nodes:
        if node.kind in ("ceiling", "roof"):
            continue
        whole = as_trimesh(node.mesh)
        cut = (whole, np.arange(len(whole.faces))) if cut_y is None else _cut(whole, cut_y)
        if cut is None or len(cut[0].faces) == 0:
            continue
        mesh, source = cut
        tris.append(np.asarray(mesh.vertices)[np.asarray(mesh.faces)])
        if source is None:
            colors.append(face_colors(mesh, node.kind))
        else:  # the node's own colours; caps in its kind's colour (a section's cut face)
            own = np.vstack([node_face_colors(node), [node_color(node.kind)]])
            colors.append(own[source])
    if not tris:
        return np.zeros((0, 3, 3)), np.zeros((0, 3))
    return np.concatenate(tris), np.concatenate(colors)


def _storeys(scene: Scene, nodes: Sequence[SceneNode]) -> list[tuple[list[SceneNode], float | None]]:
    """Nodes grouped per storey (by their ``floorN/`` path prefix) with the cut height."""
    if not scene.floors:
        return [(list(nodes), None)]
    groups: list[tuple[list[SceneNode], float | None]] = []
    for plan in scene.floors:
        prefix = f"floor{plan.index}/"
        members = [n for n in nodes if n.path.startswith(prefix)]
        groups.append((members, plan.floor_y + 1.6 * (plan.height / 3.0)))
    return groups


def _raster_triangle(tri: np.ndarray, rgb: np.ndarray, color: np.ndarray,
                     depth: np.ndarray) -> None:
    """Z-buffered fill of one screen-space triangle (x, y pixels; z towards the viewer)."""
    h, w = depth.shape
    xmin, ymin = np.floor(tri[:, :2].min(axis=0)).astype(int)
    xmax, ymax = np.ceil(tri[:, :2].max(axis=0)).astype(int)
    xmin, ymin, xmax, ymax = max(xmin, 0), max(ymin, 0), min(xmax, w - 1), min(ymax, h - 1)
    if xmin > xmax or ymin > ymax:
        return
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = tri
    area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if abs(area) < 1e-9:
        return
    ys = np.arange(ymin, ymax + 1)[:, None] + 0.5
    xs = np.arange(xmin, xmax + 1)[None, :] + 0.5
    w0 = ((bx - xs) * (cy - ys) - (by - ys) * (cx - xs)) / area
    w1 = ((cx - xs) * (ay - ys) - (cy - ys) * (ax - xs)) / area
    w2 = 1.0 - w0 - w1
    inside = (w0 >= -1e-6) & (w1 >= -1e-6) & (w2 >= -1e-6)
    z = w0 * az + w1 * bz + w2 * cz
    window = depth[ymin:ymax + 1, xmin:xmax + 1]
    nearer = inside & (z > window)
    window[nearer] = z[nearer]
    color[ymin:ymax + 1, xmin:xmax + 1][nearer] = rgb


def render_view(scene: Scene, nodes: Sequence[SceneNode], *, width: int = 1400,
                azimuth: float = 35.0, elevation: float = 50.0) -> bytes:
    """PNG bytes of a three-quarter view; storeys side by side, cut open from above."""
    camera = _camera(azimuth, elevation)
    panels = []
    for members, cut_y in _storeys(scene, nodes):
        tris, colors = _storey_triangles(members, cut_y)
        if len(tris):
            panels.append((tris, colors))
    if not panels:
        image = Image.new("RGB", (width, width // 2), _BACKGROUND)
        out = io.BytesIO()
        image.save(out, format="PNG")
        return out.getvalue()

    projected = []
    for tris, colors in panels:
        screen = tris @ camera.T  # (n, 3, 3): x right, y up, z towards viewer
        projected.append((screen, colors, tris))
    extents = [(s[..., 0].min(), s[..., 0].max(), s[..., 1].min(), s[..., 1].max())
               for s, _, _ in projected]
    gap = 0.08 * max(e[1] - e[0] for e in extents)
    total_w = sum(e[1] - e[0] for e in extents) + gap * (len(extents) + 1)
    total_h = max(e[3] - e[2] for e in extents) + 2 * gap
    scale = 2 * width / total_w
    height = int(total_h * scale) + 1
    color = np.empty((height, 2 * width, 3), dtype=np.uint8)
    color[:] = _BACKGROUND
    depth = np.full((height, 2 * width), -np.inf)

    offset_x = gap
    for (screen, colors, tris), (x0, x1, y0, y1) in zip(projected, extents):
        normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        lengths = np.linalg.norm(normals, axis=1)
        keep = lengths > 1e-12
        normals[keep] /= lengths[keep, None]
        shade = 0.55 + 0.45 * np.clip(np.abs(normals @ _LIGHT), 0, 1)
        rgb = (np.clip(colors * shade[:, None], 0, 1) * 255).astype(np.uint8)
        pixels = np.empty_like(screen)
        pixels[..., 0] = (screen[..., 0] - x0 + offset_x) * scale
        pixels[..., 1] = (y1 - screen[..., 1] + gap) * scale
        pixels[..., 2] = screen[..., 2]
        for i in np.flatnonzero(keep):
            _raster_triangle(pixels[i], rgb[i], color, depth)
        offset_x += (x1 - x0) + gap

    canvas = Image.fromarray(color)
    image = canvas.resize((width, canvas.height // 2), Image.Resampling.LANCZOS)
    out = io.BytesIO()
    image.save(out, format="PNG", optimize=True)
    return out.getvalue()


def export_view(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<name>.view.png`` (see :func:`render_view`)."""
    path = Path(out_dir) / f"{name}.view.png"
    atomic_write(path, render_view(scene, nodes))
    return [path]
