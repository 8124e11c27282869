"""The build's triangle meshes as arrays, so a build never needs trimesh to hold them.

Importing trimesh costs more CPU than meshing a whole house (it loads SciPy's spatial,
sparse and optimize packages and networkx; issue 21's measurements: 0.6 s of a 2 s
build). The meshing layer, the glTF writer and the checks only ever read a mesh's
vertices, faces, bounds and whether it is closed, so :class:`TriangleMesh` keeps those as
numpy arrays and answers them with numpy. Everything else trimesh offers (``volume``,
``contains``, ``split``, ...) is still there for the exporters and tools that want it:
such an attribute is read from a :class:`trimesh.Trimesh` made from the arrays on first
use (:meth:`TriangleMesh.as_trimesh`), so code written against trimesh keeps working.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

__all__ = ["MeshLike", "TriangleMesh", "area_centroid", "as_trimesh", "corner_means",
           "face_normals", "homogeneous", "is_watertight", "mirrors", "transform_points", "unitize",
           "volume_and_centre"]

_IDENTITY_ENTRIES = np.eye(4).ravel().tolist()

_ZERO = float(np.finfo(np.float64).resolution * 100)
"""A vector no longer than this has no direction (trimesh's ``util.TOL_ZERO``)."""

_ONES = [1.0, 1.0, 1.0]
"""Sums the rows of a ``float[n, 3]`` as trimesh sums them, ``np.dot`` with ones (BLAS):
the very call, so the rounding is trimesh's whatever order the BLAS kernel adds in."""


class MeshLike(Protocol):
    """Anything with ``vertices`` (``float[n, 3]``) and ``faces`` (``int[m, 3]``): a
    :class:`TriangleMesh`, a trimesh, :class:`cga.scene.MeshArrays`."""

    @property
    def vertices(self) -> Any: ...

    @property
    def faces(self) -> Any: ...


class TriangleMesh:
    """A triangle mesh: ``vertices`` ``float[n, 3]``, ``faces`` ``int64[m, 3]``
    (counter-clockwise seen from outside) and, for furniture, ``vertex_colors``
    ``uint8[n, 4]`` (RGBA; None when the mesh has none).

    Treat the arrays as read-only: they may be shared with the model library, and the
    trimesh made by :meth:`as_trimesh` is kept and shares them too. Any attribute this
    class does not define is looked up on that trimesh (made on first use).
    """

    __slots__ = ("vertices", "faces", "vertex_colors", "_bounds", "_trimesh")

    def __init__(self, vertices: Any, faces: Any, vertex_colors: Any = None) -> None:
        self.vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
        self.faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        self.vertex_colors = None if vertex_colors is None else np.asarray(vertex_colors)
        self._bounds: np.ndarray | None = None
        self._trimesh: "trimesh.Trimesh | None" = None

    @property
    def bounds(self) -> np.ndarray:
        """``[[min x, min y, min z], [max x, max y, max z]]`` of the vertices the faces
        use (trimesh's definition), ``float[2, 3]``."""
        if self._bounds is None:
            used = self.vertices
            if len(self.faces):
                # the vertices the faces name, each once: numpy reduces a copy per face
                # corner along its rows several times slower, and a mesh uses them all
                # but for the odd leftover
                named = np.zeros(len(used), dtype=bool)
                named[self.faces.ravel()] = True
                if not named.all():
                    used = used[named]
            if not len(used):
                raise ValueError("an empty mesh has no bounds")
            self._bounds = np.array([used.min(axis=0), used.max(axis=0)])
        return self._bounds

    @property
    def extents(self) -> np.ndarray:
        """The size of :attr:`bounds` along each axis."""
        return np.ptp(self.bounds, axis=0)

    @property
    def triangles(self) -> np.ndarray:
        """The corners of every face, ``float[m, 3, 3]``."""
        return self.vertices[self.faces]

    @property
    def triangles_center(self) -> np.ndarray:
        """The mean of each face's corners, ``float[m, 3]`` (:func:`corner_means`)."""
        return corner_means(self.triangles)

    @property
    def face_normals(self) -> np.ndarray:
        """Each face's unit normal, zero for a degenerate face (:func:`face_normals`)."""
        return face_normals(self.triangles)[0]

    @property
    def is_empty(self) -> bool:
        """Whether the mesh has no triangles."""
        return not len(self.faces)

    @property
    def is_watertight(self) -> bool:
        """Whether every edge is shared by exactly two faces (:func:`is_watertight`)."""
        return is_watertight(self.faces)

    def as_trimesh(self) -> "trimesh.Trimesh":
        """The same mesh as a :class:`trimesh.Trimesh` (not processed: vertices and faces
        as they are, with the vertex colours), made on first use and kept."""
        if self._trimesh is None:
            import trimesh

            self._trimesh = trimesh.Trimesh(vertices=self.vertices, faces=self.faces,
                                            vertex_colors=self.vertex_colors,
                                            process=False, validate=False)
        return self._trimesh

    def __getattr__(self, name: str) -> Any:
        # only called for names not found above: trimesh's other properties and methods
        if name.startswith("__") or name in TriangleMesh.__slots__:
            raise AttributeError(name)
        return getattr(self.as_trimesh(), name)

    def __repr__(self) -> str:
        return f"<TriangleMesh, {len(self.vertices)} vertices, {len(self.faces)} faces>"


def as_trimesh(mesh: "TriangleMesh | trimesh.Trimesh") -> "trimesh.Trimesh":
    """``mesh`` as a :class:`trimesh.Trimesh`, for the exporters that work with trimesh's
    own operations (sections, colours, convex hulls): a :class:`TriangleMesh`'s own
    (:meth:`TriangleMesh.as_trimesh`), a trimesh as it is."""
    return mesh.as_trimesh() if isinstance(mesh, TriangleMesh) else mesh


def is_watertight(faces: np.ndarray) -> bool:
    """Whether every edge of the triangles ``faces`` (``int[m, 3]``) is shared by exactly
    two of them: trimesh's ``is_watertight`` (edges compared without direction)."""
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if not len(faces):
        return False
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    keys = edges[:, 0] * (int(faces.max()) + 1) + edges[:, 1]
    _, counts = np.unique(keys, return_counts=True)
    return bool(np.all(counts == 2))


def unitize(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each row of ``vectors`` (``float[n, 3]``) at unit length, and which rows have a
    length (longer than :data:`_ZERO`; the others are returned as they are): trimesh's
    ``util.unitize``, its operations in its order, so the floats are its own."""
    norm = np.sqrt(np.dot(vectors * vectors, _ONES))
    valid = norm > _ZERO
    norm[valid] **= -1
    return vectors * norm.reshape((-1, 1)), valid


def face_normals(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit normal of each triangle (``float[m, 3, 3]`` corners, counter-clockwise
    seen from the side it faces) and whether it has one: a triangle whose corners' cross
    product is (nearly) zero gets a zero normal. The floats are trimesh's
    (``Trimesh.face_normals``: the same cross product and the same unitising steps)."""
    unit, valid = unitize(_crosses(triangles))
    unit[~valid] = 0.0
    return unit, valid


def corner_means(triangles: np.ndarray) -> np.ndarray:
    """The mean of each triangle's corners (``float[m, 3, 3]`` → ``float[m, 3]``), as
    ``triangles.mean(axis=1)`` computes it (a sum from zero, corner by corner, divided
    by 3: the same floats, signed zeros included) without the overhead of numpy's
    reduction machinery, which outweighs the arithmetic for the few dozen triangles of
    a wall."""
    return (0.0 + triangles[:, 0] + triangles[:, 1] + triangles[:, 2]) / 3.0


_NEXT = [1, 2, 0]
_AFTER = [2, 0, 1]


def _crosses(triangles: np.ndarray) -> np.ndarray:
    """The cross product of each triangle's edges from its first corner (trimesh's
    ``triangles.cross``): twice its area along its normal.

    Written out as ``u[i+1] v[i+2] - u[i+2] v[i+1]`` per component, the products and
    differences ``np.cross`` computes, in its order (so the same floats), without its
    axis juggling, which costs more than the arithmetic on small arrays."""
    u = triangles[:, 1] - triangles[:, 0]
    v = triangles[:, 2] - triangles[:, 1]
    return u[:, _NEXT] * v[:, _AFTER] - u[:, _AFTER] * v[:, _NEXT]


def volume_and_centre(triangles: np.ndarray) -> tuple[float, np.ndarray]:
    """The enclosed volume and the centre of mass of a closed surface's triangles
    (``float[m, 3, 3]``, facing outwards), by the divergence theorem over each triangle
    (Eberly, "Polyhedral mass properties (revisited)", 2002): the subexpressions and
    sums of trimesh's ``triangles.mass_properties``, so the floats are the same. The
    centre is not finite when the volume is zero."""
    triangles = np.asarray(triangles, dtype=np.float64)
    crosses = _crosses(triangles)
    a, b, c = triangles[:, 0, :], triangles[:, 1, :], triangles[:, 2, :]
    f1 = a + b + c
    f2 = a**2 + b**2 + a * b + c * f1
    integral = np.zeros((4, len(f1)))
    integral[0] = crosses[:, 0] * f1[:, 0]
    integral[1:4] = (crosses * f2).T
    integrated = integral.sum(axis=1) / np.array([6, 24, 24, 24], dtype=np.float64)
    volume = float(integrated[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        return volume, integrated[1:4] / integrated[0]


def area_centroid(triangles: np.ndarray) -> np.ndarray:
    """The area-weighted mean of the triangles' centres (``float[m, 3, 3]`` corners), or
    their plain mean when every triangle is degenerate: trimesh's ``Trimesh.centroid``."""
    areas = np.sqrt((_crosses(triangles)**2).sum(axis=1)) / 2.0
    centres = corner_means(triangles)
    if not areas.sum() > 0:
        return np.asarray(centres.mean(axis=0))
    return np.asarray(np.average(centres, weights=areas, axis=0))


def _near_identity(matrix: np.ndarray) -> bool:
    """``np.abs(matrix - identity).max() < 1e-8`` (trimesh's test; False if an entry is
    NaN), on the 16 floats: numpy's reduction costs more than the test on a 4×4."""
    entries = matrix.ravel().tolist()
    return all(abs(a - b) < 1e-8 for a, b in zip(entries, _IDENTITY_ENTRIES))


def transform_points(points: np.ndarray, matrix: np.ndarray,
                     stack: np.ndarray | None = None) -> np.ndarray:
    """``points`` (``float[n, 3]``) moved by the 4×4 affine ``matrix``, computed as
    :func:`trimesh.transform_points` computes it (one product with the homogeneous
    points; a matrix within 1e-8 of the identity leaves them as they are), so the floats
    are the same bit for bit.

    ``stack`` is :func:`homogeneous` of ``points``, for a caller that moves the same
    points many times (a furniture model posed for each of its items) and keeps it."""
    points = np.asarray(points, dtype=np.float64)
    matrix = np.asarray(matrix, dtype=np.float64)
    if not len(points) or _near_identity(matrix):
        return np.ascontiguousarray(points.copy())
    if stack is None:
        stack = homogeneous(points)
    return np.dot(matrix, stack.T).T[:, :3]


def homogeneous(points: np.ndarray) -> np.ndarray:
    """``points`` (``float[n, 3]``) as homogeneous rows ``(x, y, z, 1)``, ``float[n, 4]``:
    trimesh's ``np.column_stack((points, ones))``, made directly."""
    stack = np.empty((len(points), 4))
    stack[:, :3] = points
    stack[:, 3] = 1.0
    return stack


def mirrors(matrix: np.ndarray) -> bool:
    """Whether the affine ``matrix`` (4×4) turns shapes inside out: whether its linear
    part has a negative determinant, worked out as the triple product of its rows.

    For the frames the meshing layer builds (turns, moves, scales far from zero) the
    sign is that of ``np.linalg.det``, at a fraction of its cost on a 3×3 matrix."""
    (a, b, c), (d, e, f), (g, h, i) = matrix[:3, :3].tolist()
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) < 0
