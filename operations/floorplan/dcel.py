"""A doubly connected edge list (half-edge structure) for floor plans.

``make_floor`` partitions a storey by cutting faces of this structure
(docs/architecture.md, "Floor plans"): a room is a bounded face, a wall segment is a pair
of twin half-edges, an outer wall is an edge whose twin lies on the unbounded (outside)
face. Cutting a face inserts vertices into the edges the cut meets, so a T-junction is a
proper vertex and two rooms share exactly the half-edges of their common wall.

Conventions: coordinates are plan ``(x, z)`` in metres. Bounded faces are traversed
counter-clockwise (positive signed area in ``(x, z)``), so every half-edge has its face
on the left; the outside face's cycle runs clockwise around the footprint. Every face has
exactly one boundary cycle (footprints are simple polygons, without courtyards).
Half-edges are never deleted, so ``id`` is the index into :attr:`DCEL.half_edges`; the two
halves of an edge share :attr:`HalfEdge.edge`, a dense edge number that floor plans use
as the wall id.

References
----------
M. de Berg, O. Cheong, M. van Kreveld, M. Overmars, *Computational Geometry: Algorithms
and Applications*, 3rd ed., Springer 2008, §2.2 (doubly connected edge lists).
Room-generation thesis, §2.1.3 and §5.1.1 (Halbkanten-Datenstruktur).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

from cga.model import OUTSIDE

from .errors import PartitionError

__all__ = ["EPS", "Vertex", "HalfEdge", "Face", "DCEL", "signed_area", "point_in_ring"]

EPS = 1e-7
"""Distance (m) under which two points are the same point."""

Point = tuple[float, float]


class Vertex:
    """A point of the plan; ``edge`` is one half-edge that starts here."""

    __slots__ = ("id", "x", "z", "edge")

    def __init__(self, id: int, x: float, z: float):
        self.id = id
        self.x = x
        self.z = z
        self.edge: HalfEdge | None = None

    @property
    def point(self) -> Point:
        return (self.x, self.z)

    def outgoing(self) -> list["HalfEdge"]:
        """The half-edges that start at this vertex, turning around it."""
        out = []
        e = self.edge
        while e is not None:
            out.append(e)
            e = e.twin.next
            if e is self.edge:
                break
        return out

    def __repr__(self) -> str:
        return f"Vertex({self.id}, {self.x:g}, {self.z:g})"


class HalfEdge:
    """One direction of an edge: from ``origin`` to ``twin.origin``, ``face`` on its left."""

    __slots__ = ("id", "edge", "origin", "twin", "next", "prev", "face")

    def __init__(self, id: int, edge: int, origin: Vertex):
        self.id = id
        self.edge = edge
        self.origin = origin
        self.twin: HalfEdge = None  # type: ignore[assignment]  # set right after creation
        self.next: HalfEdge = None  # type: ignore[assignment]
        self.prev: HalfEdge = None  # type: ignore[assignment]
        self.face: Face = None  # type: ignore[assignment]

    @property
    def destination(self) -> Vertex:
        return self.twin.origin

    @property
    def start(self) -> Point:
        return self.origin.point

    @property
    def end(self) -> Point:
        return self.twin.origin.point

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    def __repr__(self) -> str:
        return f"HalfEdge({self.id}, {self.start} -> {self.end}, face {self.face.id})"


class Face:
    """A face: a room, or the outside (``id`` == :data:`cga.model.OUTSIDE`)."""

    __slots__ = ("id", "edge")

    def __init__(self, id: int):
        self.id = id
        self.edge: HalfEdge = None  # type: ignore[assignment]

    @property
    def is_outside(self) -> bool:
        return self.id == OUTSIDE

    def __repr__(self) -> str:
        return "Face(outside)" if self.is_outside else f"Face({self.id})"


def signed_area(points: Sequence[Point]) -> float:
    """Shoelace area of a closed ring (positive when counter-clockwise in ``(x, z)``)."""
    total = 0.0
    n = len(points)
    for i in range(n):
        x0, z0 = points[i]
        x1, z1 = points[(i + 1) % n]
        total += x0 * z1 - x1 * z0
    return total / 2.0


class DCEL:
    """A planar subdivision of a simple polygon into faces.

    Build one with :meth:`from_polygon` (one face) or :meth:`from_polygons` (faces that
    tile a region), then refine it with :meth:`split_edge` and :meth:`split_face`.
    ``faces[i]`` is the bounded face with id ``i``; :attr:`outside` is the unbounded face.
    """

    def __init__(self) -> None:
        self.vertices: list[Vertex] = []
        self.half_edges: list[HalfEdge] = []
        self.faces: list[Face] = []
        self.outside = Face(OUTSIDE)
        self.edge_count = 0

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_polygon(cls, points: Sequence[Point]) -> "DCEL":
        """One bounded face (id 0) from a simple counter-clockwise polygon."""
        return cls.from_polygons([points])

    @classmethod
    def from_polygons(cls, polygons: Sequence[Sequence[Point]]) -> "DCEL":
        """Faces ``0..n-1`` from polygons that tile a simply connected region.

        Parameters
        ----------
        polygons
            Counter-clockwise vertex rings (no repeated closing point). Where two polygons
            share a boundary, both must list the same vertices on it (T-junctions
            included), so that each shared segment appears once in each direction.

        Raises
        ------
        PartitionError
            If a ring is degenerate or clockwise, two rings use the same directed segment
            (overlap), or the boundary of the union is not a single simple cycle.

        Notes
        -----
        O(V + E) with hashing of vertex coordinates.
        """
        dcel = cls()
        by_point: dict[tuple[float, float], Vertex] = {}
        directed: dict[tuple[int, int], HalfEdge] = {}

        def vertex(p: Point) -> Vertex:
            key = (round(p[0] / EPS) * EPS, round(p[1] / EPS) * EPS)
            v = by_point.get(key)
            if v is None:
                v = dcel._new_vertex(float(p[0]), float(p[1]))
                by_point[key] = v
            return v

        for index, ring in enumerate(polygons):
            if len(ring) < 3 or signed_area(ring) <= EPS:
                raise PartitionError(f"polygon {index} is degenerate or not counter-clockwise")
            face = Face(index)
            dcel.faces.append(face)
            verts = [vertex(p) for p in ring]
            cycle = []
            for a, b in zip(verts, verts[1:] + verts[:1]):
                if a is b:
                    raise PartitionError(f"polygon {index} repeats the point {a.point}")
                if (a.id, b.id) in directed:
                    raise PartitionError(f"polygons overlap along {a.point} -> {b.point}")
                twin = directed.get((b.id, a.id))
                h = dcel._new_half_edge(a, twin.edge if twin else dcel._next_edge_id())
                h.face = face
                directed[(a.id, b.id)] = h
                if twin is not None:
                    h.twin, twin.twin = twin, h
                cycle.append(h)
            dcel._link_cycle(cycle)
            face.edge = cycle[0]

        # Half-edges without a twin bound the union: give them outside twins.
        outer_from: dict[int, HalfEdge] = {}
        for h in list(dcel.half_edges):
            if h.twin is None:
                o = dcel._new_half_edge(h.next.origin, h.edge)
                o.face = dcel.outside
                o.twin, h.twin = h, o
                if o.origin.id in outer_from:
                    raise PartitionError(f"the region's boundary touches itself at {o.origin.point}")
                outer_from[o.origin.id] = o
        if not outer_from:
            raise PartitionError("the polygons do not bound a region")
        for o in outer_from.values():
            o.next = outer_from[o.destination.id]
            o.next.prev = o
        start = next(iter(outer_from.values()))
        dcel.outside.edge = start
        if len(dcel._cycle(start)) != len(outer_from):
            raise PartitionError("the polygons' union has a hole or is not connected")
        return dcel

    # ------------------------------------------------------------------ queries
    def face(self, face_id: int) -> Face:
        """The face with this id (:data:`cga.model.OUTSIDE` gives the outside face)."""
        return self.outside if face_id == OUTSIDE else self.faces[face_id]

    def boundary(self, face: Face) -> list[HalfEdge]:
        """The half-edges around ``face`` in ``next`` order (counter-clockwise for rooms)."""
        return self._cycle(face.edge)

    def points(self, face: Face) -> list[Point]:
        """The boundary vertices of ``face`` (T-junction vertices included)."""
        return [h.origin.point for h in self._cycle(face.edge)]

    def area(self, face: Face) -> float:
        """Area of a bounded face (m²)."""
        return signed_area(self.points(face))

    def outer_boundary(self) -> list[HalfEdge]:
        """The room-side half-edges along the footprint, counter-clockwise.

        Each returned half-edge belongs to a room and has the outside face as its twin's
        face: these are the outer walls in order around the building, starting with the
        oldest one.
        """
        ring = [o.twin for o in reversed(self._cycle(self.outside.edge))]
        first = min(range(len(ring)), key=lambda i: ring[i].id)
        return ring[first:] + ring[:first]

    def edges(self) -> Iterator[HalfEdge]:
        """One half-edge per edge, in edge-number order (the first half created)."""
        seen: set[int] = set()
        for h in self.half_edges:
            if h.edge not in seen:
                seen.add(h.edge)
                yield h

    def shared_edges(self, a: Face | int, b: Face | int) -> list[HalfEdge]:
        """The half-edges of face ``a`` whose twin lies on face ``b`` (their common wall).

        Either face may be the outside; the result is in ``a``'s boundary order.
        """
        fa = self.face(a) if isinstance(a, int) else a
        fb = self.face(b) if isinstance(b, int) else b
        return [h for h in self._cycle(fa.edge) if h.twin.face is fb]

    def neighbours(self, face: Face | int) -> list[int]:
        """Ids of the faces sharing at least one edge with ``face`` (sorted; may include
        :data:`cga.model.OUTSIDE`)."""
        f = self.face(face) if isinstance(face, int) else face
        return sorted({h.twin.face.id for h in self._cycle(f.edge)})

    def adjacency(self) -> dict[int, list[int]]:
        """Face id → sorted neighbour ids, for every bounded face."""
        return {f.id: self.neighbours(f) for f in self.faces}

    # ------------------------------------------------------------------ editing
    def split_edge(self, edge: HalfEdge, point: Point) -> Vertex:
        """Insert a vertex at ``point`` strictly inside ``edge`` (and its twin).

        Afterwards ``edge`` ends at the new vertex and ``edge.next`` starts there; both
        faces keep their ids. The edge number of ``edge`` is kept by the part from
        ``edge.origin`` to the new vertex; the other part gets a new number.

        Raises
        ------
        PartitionError
            If ``point`` is not on the edge or coincides with one of its ends.

        Notes
        -----
        O(1).
        """
        a, b = edge.start, edge.end
        if not _on_open_segment(point, a, b):
            raise PartitionError(f"{point} is not strictly inside the edge {a} -> {b}")
        twin = edge.twin
        w = self._new_vertex(float(point[0]), float(point[1]))
        new_edge = self._next_edge_id()
        e2 = self._new_half_edge(w, new_edge)  # w -> b, along edge
        t2 = self._new_half_edge(w, edge.edge)  # w -> a, along twin
        e2.face, t2.face = edge.face, twin.face
        # edge: a -> w, twin: b -> w
        edge.twin, t2.twin = t2, edge
        e2.twin, twin.twin = twin, e2
        twin.edge = new_edge
        e2.next, e2.prev = edge.next, edge
        edge.next.prev = e2
        edge.next = e2
        t2.next, t2.prev = twin.next, twin
        twin.next.prev = t2
        twin.next = t2
        w.edge = e2
        return w

    def split_face(self, face: Face, p: Point, q: Point) -> HalfEdge:
        """Cut ``face`` along the segment ``p``–``q`` between two points of its boundary.

        Points inside an edge become new vertices (on both sides of that edge, so the
        neighbouring face gains the T-junction too). The new edge is a twin pair.

        Returns
        -------
        HalfEdge
            The new half-edge from ``p`` to ``q``. Its face is ``face`` (which keeps its
            id); its twin's face is the new face, numbered ``len(faces)`` before the call.

        Raises
        ------
        PartitionError
            If ``face`` is the outside, a point is not on the boundary, or the open
            segment leaves the face or touches its boundary.

        Notes
        -----
        O(n) in the number of boundary edges of ``face``.
        """
        if face.is_outside:
            raise PartitionError("the outside face cannot be split")
        if math.dist(p, q) <= EPS:
            raise PartitionError("the cut segment has zero length")
        ring = self.points(face)
        mid = ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)
        if not point_in_ring(mid, ring) or _segment_touches_ring(p, q, ring):
            raise PartitionError(f"the segment {p} -> {q} is not a chord of face {face.id}")
        a = self._boundary_edge_at(face, p)
        b = self._boundary_edge_at(face, q)
        return self._connect(a, b)

    # ------------------------------------------------------------------ internals
    def _new_vertex(self, x: float, z: float) -> Vertex:
        v = Vertex(len(self.vertices), x, z)
        self.vertices.append(v)
        return v

    def _next_edge_id(self) -> int:
        self.edge_count += 1
        return self.edge_count - 1

    def _new_half_edge(self, origin: Vertex, edge: int) -> HalfEdge:
        h = HalfEdge(len(self.half_edges), edge, origin)
        self.half_edges.append(h)
        if origin.edge is None:
            origin.edge = h
        return h

    @staticmethod
    def _link_cycle(cycle: list[HalfEdge]) -> None:
        for h, n in zip(cycle, cycle[1:] + cycle[:1]):
            h.next, n.prev = n, h

    def _cycle(self, start: HalfEdge) -> list[HalfEdge]:
        out = [start]
        h = start.next
        limit = len(self.half_edges)
        while h is not start:
            out.append(h)
            h = h.next
            if len(out) > limit:
                raise RuntimeError(f"broken next cycle at half-edge {start.id}")
        return out

    def _boundary_edge_at(self, face: Face, p: Point) -> HalfEdge:
        """The half-edge of ``face`` starting at ``p``, splitting an edge if needed."""
        for h in self._cycle(face.edge):
            if math.dist(h.start, p) <= EPS:
                return h
        for h in self._cycle(face.edge):
            if _on_open_segment(p, h.start, h.end):
                self.split_edge(h, p)
                return h.next
        raise PartitionError(f"{p} is not on the boundary of face {face.id}")

    def _connect(self, a: HalfEdge, b: HalfEdge) -> HalfEdge:
        """Join ``a.origin`` to ``b.origin`` inside their common face."""
        face = a.face
        edge = self._next_edge_id()
        h = self._new_half_edge(a.origin, edge)  # a.origin -> b.origin
        g = self._new_half_edge(b.origin, edge)  # b.origin -> a.origin
        h.twin, g.twin = g, h
        pa, pb = a.prev, b.prev
        h.prev, pa.next = pa, h
        h.next, b.prev = b, h
        g.prev, pb.next = pb, g
        g.next, a.prev = a, g
        new_face = Face(len(self.faces))
        self.faces.append(new_face)
        h.face = face
        face.edge = h
        new_face.edge = g
        for e in self._cycle(g):
            e.face = new_face
        return h


def _cross(o: Point, a: Point, b: Point) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _on_segment(p: Point, a: Point, b: Point) -> bool:
    """``p`` lies on the closed segment ``a``–``b`` (within :data:`EPS`)."""
    length = math.dist(a, b)
    if length <= EPS:
        return math.dist(p, a) <= EPS
    if abs(_cross(a, b, p)) / length > EPS:
        return False
    t = ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / length
    return -EPS <= t <= length + EPS


def _on_open_segment(p: Point, a: Point, b: Point) -> bool:
    return _on_segment(p, a, b) and math.dist(p, a) > EPS and math.dist(p, b) > EPS


def point_in_ring(p: Point, ring: Sequence[Point]) -> bool:
    """Whether ``p`` lies strictly inside the closed ring (even-odd rule; points on the
    boundary count as outside)."""
    inside = False
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if _on_segment(p, a, b):
            return False
        if (a[1] > p[1]) != (b[1] > p[1]):
            x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            if x > p[0]:
                inside = not inside
    return inside


def _segment_touches_ring(p: Point, q: Point, ring: Sequence[Point]) -> bool:
    """Whether the open segment ``p``–``q`` meets the ring anywhere."""
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        # A ring vertex on the open segment, or the segment's end inside an edge's
        # interior while running along it, both count as touching.
        if _on_open_segment(a, p, q):
            return True
        d1, d2 = _cross(p, q, a), _cross(p, q, b)
        d3, d4 = _cross(a, b, p), _cross(a, b, q)
        if ((d1 > EPS and d2 < -EPS) or (d1 < -EPS and d2 > EPS)) and (
                (d3 > EPS and d4 < -EPS) or (d3 < -EPS and d4 > EPS)):
            return True
    return False
