"""The furniture model library: find a model by name, load it once, place it in a plan.

``add_furniture`` needs each model's size, the physics check its convex parts and mass,
the exporters its coloured mesh. All of them ask a :class:`ModelLibrary`, which searches
the user's folders before the models shipped in ``cga.furniture_models`` and loads each file once.

Model files (docs/models.md) are Wavefront OBJ in metres, y up, front toward −z, origin at the
centre of the footprint on the floor. Each OBJ group (``g``) or object (``o``) is one
convex part, so physics can use the parts as a compound body directly. Optional header
comments give the physical and visual properties::

    # density 450          kg/m³ of the parts' material (mass = parts' volume × density)
    # color 0.55 0.38 0.22 the model's main colour, linear RGB in 0..1

Vertex colours (``v x y z r g b``) give each part its own colour; trimesh loads them and
the glTF exporter keeps them.

Parsing a model (trimesh's OBJ reader, the convexity test and volume of every part) costs
far more than reading arrays back, so the parsed parts are kept in the on-disk cache
(:mod:`cga.cache`, kind ``models``), keyed by the file's text and trimesh's version. A
record's trimesh objects are made from the arrays only when something asks for
:attr:`FurnitureModel.parts` or :attr:`~FurnitureModel.mesh`: ``cga check`` and the layout
need only sizes, and never import trimesh.
"""

from __future__ import annotations

import importlib.util
import io
import math
import os
import re
import zipfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from functools import cache, cached_property
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np

from cga.cache import digest, has_entry, read_entry, write_entry
from cga.errors import CGAError, ResourceNotFoundError, excerpt
from cga.mesh import TriangleMesh
from cga.provenance import note_input
from cga.resources import is_regular_file, shipped_dir

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    from cga.sandbox import Sandbox

__all__ = [
    "DEFAULT_COLOR",
    "DEFAULT_DENSITY",
    "FurnitureModel",
    "ModelFileError",
    "ModelGeometry",
    "MAX_MODEL_PARTS",
    "MAX_MODEL_VERTICES",
    "ModelLibrary",
    "default_library",
    "grammar_library",
    "grammar_model_dirs",
    "is_convex_part",
    "load_model",
    "name_candidates",
    "normalize_name",
    "part_volume",
]

DEFAULT_DENSITY = 500.0
"""kg/m³ of a model whose file declares no ``# density`` (light timber)."""

DEFAULT_COLOR = (0.7, 0.7, 0.7)
"""Main colour of a model whose file declares no ``# color``."""

_CONVEX_TOLERANCE = 1e-3
"""A part is convex when its volume is within this fraction of its convex hull's."""

MAX_MODEL_VERTICES = 50_000
"""Most vertices a furniture model file may have (faces: twice as many). The shipped
models have a few hundred; physics and every export handle each item's mesh."""

MAX_MODEL_PARTS = 500
"""Most parts (OBJ groups and objects) a model may have: each is a convex piece that
physics simulates; the shipped models have a few dozen at most."""

_PARSE_ERRORS = (ValueError, IndexError, KeyError, TypeError, AttributeError,
                 AssertionError, OverflowError, ZeroDivisionError)
"""What trimesh's OBJ reader raises on malformed text (face indices out of range, a
word where a number belongs, ...)."""

_CACHE_KIND = "models"
_CACHE_FORMAT = "cga-model-2"
"""Version of the cached record's layout; part of the cache key."""

_VERTEX_LINE = re.compile(r"^[ \t]*v[ \t]", re.MULTILINE)
_FACE_LINE = re.compile(r"^[ \t]*f[ \t]", re.MULTILINE)
_PART_LINE = re.compile(r"^[ \t]*[go][ \t]", re.MULTILINE)
_SEPARATORS = re.compile(r"[\s_\-]+")
_TRAILING_NUMBER = re.compile(r"\d+$")
_HEADER = re.compile(r"^#\s*(density|color)\b(.*)$", re.IGNORECASE)


class ModelFileError(CGAError):
    """A model file exists but cannot be used (unreadable, no faces, bad header)."""

    def __init__(self, path: Path, message: str):
        super().__init__(f"{path}: {message}")
        self.path = path


def normalize_name(name: str) -> str:
    """The canonical form of a model name: lower case without spaces, ``_`` or ``-``.

    ``"Double Bed"``, ``"double_bed"`` and ``"doubleBed"`` all give ``"doublebed"``.
    """
    return _SEPARATORS.sub("", name).lower()


def name_candidates(name: str) -> tuple[str, ...]:
    """File stems tried for ``name``, in order: the full name, then without a numeric suffix.

    A numeric suffix repeats a model in a rule table (``chair1`` is another ``chair``),
    but a model whose own name ends in digits is still found, as the full name comes first.
    """
    full = normalize_name(name)
    base = _TRAILING_NUMBER.sub("", full)
    return (full, base) if base and base != full else (full,)


def part_volume(part: trimesh.Trimesh) -> float:
    """The part's volume (m³), or its convex hull's when it does not bound a volume."""
    if part.is_volume:
        return float(part.volume)
    return float(part.convex_hull.volume)


def is_convex_part(part: trimesh.Trimesh) -> bool:
    """Whether ``part`` is a closed convex solid (watertight, volume ≈ hull volume)."""
    if not part.is_watertight or not part.is_volume:
        return False
    hull = float(part.convex_hull.volume)
    return abs(hull - float(part.volume)) <= _CONVEX_TOLERANCE * hull


@dataclass(frozen=True, eq=False)
class ModelGeometry:
    """A parsed model's parts as arrays (model frame, metres) and what is measured from
    them once: the trimesh objects are made on first use and shared by every record of
    the same file, so treat them as read-only.

    ``colors`` holds each part's RGBA vertex colours (uint8), or None for a part whose
    file gave none; ``names`` the parts' OBJ group (or object) names, which name each
    part's material class (``part_3_wood``, :mod:`cga.appearance`).
    """

    vertices: tuple[np.ndarray, ...]
    faces: tuple[np.ndarray, ...]
    colors: tuple[np.ndarray | None, ...]
    size: tuple[float, float, float]
    volume: float
    convex_parts: bool
    names: tuple[str, ...] = ()

    @cached_property
    def parts(self) -> tuple[trimesh.Trimesh, ...]:
        import trimesh

        return tuple(trimesh.Trimesh(vertices=v, faces=f, vertex_colors=c, process=False)
                     for v, f, c in zip(self.vertices, self.faces, self.colors))

    @cached_property
    def closed_parts(self) -> tuple[bool, ...]:
        """Whether each part encloses a volume (trimesh's ``is_volume``): a turn and a
        scale by positive factors keep it, so it holds for every posed copy."""
        return tuple(bool(part.is_volume) for part in self.parts)

    @cached_property
    def mesh(self) -> trimesh.Trimesh:
        import trimesh

        return cast(trimesh.Trimesh, trimesh.util.concatenate(self.parts))

    @cached_property
    def joined(self) -> TriangleMesh:
        """All parts as one mesh, as arrays: the vertices, faces and vertex colours of
        :attr:`mesh` (trimesh's ``util.concatenate``: parts one after another, each part's
        faces offset by the vertices before it), made without trimesh."""
        ends = np.cumsum([0, *(len(v) for v in self.vertices)])
        faces = np.concatenate([np.zeros((0, 3), dtype=np.int64),
                                *(f + start for f, start in zip(self.faces, ends))])
        vertices = np.concatenate([np.zeros((0, 3)), *self.vertices])
        if all(c is None for c in self.colors):
            colors = None
        elif all(c is not None for c in self.colors):
            colors = np.concatenate(cast("list[np.ndarray]", list(self.colors)))
        else:  # parts with and without colours: trimesh's defaults fill the gaps
            colors = np.asarray(getattr(self.mesh.visual, "vertex_colors"))
        return TriangleMesh(vertices, faces, colors)

@dataclass(frozen=True, eq=False)
class FurnitureModel:
    """A loaded model in its own frame (metres, y up, front toward −z, origin on the floor
    at the centre of the footprint).

    ``size`` is the axis-aligned extent ``(width x, height y, depth z)``. ``parts`` are the
    pieces of the model (one per OBJ group), ``mesh`` is all parts in one mesh; both carry
    per-vertex colours and are shared by every user of the library, so treat them as
    read-only (copy before transforming). ``convex_parts`` is False when some part is not
    a closed convex solid; physics then decomposes the mesh itself (V-HACD).
    """

    name: str
    size: tuple[float, float, float]
    geometry: ModelGeometry
    color: tuple[float, float, float]
    density: float
    path: Path

    @property
    def parts(self) -> tuple[trimesh.Trimesh, ...]:
        return self.geometry.parts

    @property
    def mesh(self) -> trimesh.Trimesh:
        return self.geometry.mesh

    @property
    def convex_parts(self) -> bool:
        return self.geometry.convex_parts

    @property
    def part_names(self) -> tuple[str, ...]:
        """The parts' OBJ group names, in part order (:attr:`ModelGeometry.names`)."""
        return self.geometry.names

    @property
    def volume(self) -> float:
        """Sum of the parts' volumes (m³); see :func:`part_volume`."""
        return self.geometry.volume

    @property
    def mass(self) -> float:
        """Mass at the model's own size (kg): volume × density."""
        return self.volume * self.density


class ModelLibrary:
    """Finds models by name in ``search_dirs`` (in order) and loads each file once.

    Parameters
    ----------
    search_dirs
        Folders holding ``<name>.obj`` files, most specific first. Folders that do not
        exist are skipped (and still listed when a model is not found).
    sandbox
        The folders a model file may lie in after following links (:mod:`cga.sandbox`);
        a file that links out of them is refused. None loads any file.

    Notes
    -----
    Names match case-insensitively ignoring spaces, ``_`` and ``-``; a trailing number is
    dropped when the full name is not found in any folder (:func:`name_candidates`), so
    ``Bookshelf2`` finds ``bookshelf.obj`` unless some folder has ``bookshelf2.obj``.
    Each folder is listed once, on its first lookup; a library is meant for one build.
    """

    def __init__(self, search_dirs: Sequence[Path], sandbox: "Sandbox | None" = None):
        self.search_dirs: tuple[Path, ...] = tuple(Path(d) for d in search_dirs)
        self.sandbox = sandbox
        self._index: dict[Path, dict[str, Path]] = {}
        self._by_path: dict[Path, FurnitureModel] = {}
        self._by_name: dict[str, FurnitureModel] = {}

    def get(self, name: str) -> FurnitureModel:
        """The model called ``name``.

        Raises
        ------
        ResourceNotFoundError
            No folder holds a matching file; the message lists every folder searched.
        ResourceAccessError
            The file found links out of the sandbox.
        ModelFileError
            The file found cannot be loaded.
        """
        key = normalize_name(name)
        model = self._by_name.get(key)
        if model is None:
            path = self.find(name)
            model = self._by_path.get(path)
            if model is None:
                model = _load_shared(path)
                self._by_path[path] = model
            self._by_name[key] = model
        return model

    def check(self, name: str) -> Path:
        """The file :meth:`get` loads for ``name``, known to load, without loading it
        when it need not: a file whose bytes the on-disk cache holds parsed before (only
        valid files are stored), so ``cga check`` reads no arrays.

        Raises
        ------
        The errors of :meth:`get`.
        """
        model = self._by_name.get(normalize_name(name))
        if model is not None:
            return model.path
        path = self.find(name)
        if path not in self._by_path and not _is_cached(path):
            self.get(name)
        return path

    def find(self, name: str) -> Path:
        """The file that :meth:`get` loads for ``name`` (see the class notes).

        Raises
        ------
        ResourceNotFoundError
            No folder holds a matching file.
        """
        for stem in name_candidates(name):
            for folder in self.search_dirs:
                path = self._folder_index(folder).get(stem)
                if path is not None:
                    if self.sandbox is not None and not self.sandbox.contains(path):
                        raise self.sandbox.refusal("model", str(path))
                    note_input(path)  # a batch records what each house was made from
                    return path
        raise ResourceNotFoundError("furniture model", name,
                                    [str(d) for d in self.search_dirs])

    def names(self) -> list[str]:
        """Every model name available, sorted (earlier folders shadow later ones)."""
        found: set[str] = set()
        for folder in self.search_dirs:
            found.update(self._folder_index(folder))
        return sorted(found)

    def _folder_index(self, folder: Path) -> dict[str, Path]:
        index = self._index.get(folder)
        if index is None:
            index = {}
            if folder.is_dir():
                for path in sorted(folder.iterdir()):
                    if path.suffix.lower() == ".obj" and is_regular_file(path):
                        index.setdefault(normalize_name(path.stem), path)
            self._index[folder] = index
        return index


_PARSED: dict[Path, tuple[int, int, FurnitureModel]] = {}
"""Models parsed in this process: resolved path → (mtime_ns, size, model)."""


def _load_shared(path: Path) -> FurnitureModel:
    """:func:`load_model`, parsing each version of a file once per process.

    Loading (OBJ parsing, the convexity test of every part) costs far more than a small
    build's layout, and every build of a batch uses the same files. A library still hands
    out its own :class:`FurnitureModel` record per file; the read-only geometry behind it
    is shared. A file changed on disk (other modification time or size) is parsed again.
    """
    try:
        stat = path.stat()
        key = path.resolve()
    except OSError:
        return load_model(path)
    cached = _PARSED.get(key)
    if cached is None or cached[:2] != (stat.st_mtime_ns, stat.st_size):
        cached = _PARSED[key] = (stat.st_mtime_ns, stat.st_size, load_model(path))
    return replace(cached[2])


def load_model(path: Path) -> FurnitureModel:
    """Load one OBJ file as a :class:`FurnitureModel` (no caching in memory; use a library).

    Each group or object of the file becomes a part (a file without either is one part).
    The parts are moved so the model's lowest point is at y = 0 and the centre of its
    footprint at the origin; files made to the convention are not changed. A file whose
    bytes were parsed before is read back from the on-disk cache (only valid files are
    stored, so a hit needs no checks).

    Raises
    ------
    ModelFileError
        The file cannot be read or parsed, has no faces, or has a bad header value.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ModelFileError(path, f"cannot read the OBJ file ({exc.strerror})") from None
    key = _cache_key(data)
    record = _from_cache(read_entry(_CACHE_KIND, key, ".npz"))
    if record is None:
        text = _obj_text(path, data)
        density, color = _read_header(path, text)
        record = _parse_geometry(path, text), density, color
        write_entry(_CACHE_KIND, key, _to_cache(*record), ".npz")
    geometry, density, color = record
    return FurnitureModel(name=normalize_name(path.stem), size=geometry.size,
                          geometry=geometry, color=color, density=density, path=path)


def _cache_key(data: bytes) -> str:
    """The on-disk cache key of a model file's bytes (a new trimesh parses anew)."""
    return digest(_CACHE_FORMAT, _trimesh_install(), data)


@cache
def _trimesh_install() -> str:
    """Which trimesh parsed the cached models: where its package file is and when it was
    written, so installing another version (or the same one again) misses the cache.

    Read from the file system without importing trimesh (``cga check`` never imports
    it) or its package metadata (``importlib.metadata`` costs more than the whole
    model check)."""
    spec = importlib.util.find_spec("trimesh")
    if spec is None or spec.origin is None:
        return "trimesh: not installed"
    stat = os.stat(spec.origin)
    return f"{spec.origin}:{stat.st_mtime_ns}:{stat.st_size}"


def _is_cached(path: Path) -> bool:
    """Whether the on-disk cache holds ``path``'s current bytes, parsed."""
    try:
        data = path.read_bytes()
    except OSError:
        return False
    return has_entry(_CACHE_KIND, _cache_key(data), ".npz")


_Record = tuple[ModelGeometry, float, tuple[float, float, float]]
"""A parsed model file: its geometry, density and colour."""


def _to_cache(geometry: ModelGeometry, density: float, color: tuple[float, float, float]
              ) -> bytes:
    """A parsed file as an ``.npz`` archive of six arrays: the parts' vertices, faces and
    colours end to end, per part its vertex and face counts and whether it has colours,
    and the numbers measured once (size, volume, convexity, density, colour)."""
    counts = np.array([[len(v), len(f), c is not None] for v, f, c in
                       zip(geometry.vertices, geometry.faces, geometry.colors)], dtype=np.int64)
    colors = [c if c is not None else np.zeros((len(v), 4), np.uint8)
              for v, c in zip(geometry.vertices, geometry.colors)]
    meta = np.array([*geometry.size, geometry.volume, float(geometry.convex_parts), density,
                     *color])
    buffer = io.BytesIO()
    np.savez(buffer, allow_pickle=False, counts=counts, meta=meta,
             vertices=np.concatenate(geometry.vertices), faces=np.concatenate(geometry.faces),
             colors=np.concatenate(colors), names=np.array(geometry.names, dtype=str))
    return buffer.getvalue()


def _from_cache(data: bytes | None) -> _Record | None:
    """The record :func:`_to_cache` wrote, or None (no entry, or a damaged one)."""
    if data is None:
        return None
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as archive:
            counts, meta = archive["counts"], archive["meta"].tolist()
            vertices, faces, colors = archive["vertices"], archive["faces"], archive["colors"]
            names = tuple(str(n) for n in archive["names"])
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    v_ends, f_ends = np.cumsum(counts[:, 0])[:-1], np.cumsum(counts[:, 1])[:-1]
    geometry = ModelGeometry(
        vertices=tuple(np.split(vertices, v_ends)), faces=tuple(np.split(faces, f_ends)),
        colors=tuple(c if has else None for c, has in zip(np.split(colors, v_ends), counts[:, 2])),
        size=(meta[0], meta[1], meta[2]), volume=meta[3], convex_parts=bool(meta[4]),
        names=names)
    return geometry, meta[5], (meta[6], meta[7], meta[8])


def _parse_geometry(path: Path, text: str) -> ModelGeometry:
    """Parse the OBJ text with trimesh into a :class:`ModelGeometry` (parts moved to the
    model frame's convention, volume and convexity measured)."""
    import trimesh

    try:
        scene = trimesh.load_scene(io.BytesIO(text.encode("utf-8")), file_type="obj",
                                   split_groups=True, split_objects=True, group_material=False)
    except _PARSE_ERRORS as exc:
        raise ModelFileError(path, f"cannot read the OBJ file ({excerpt(str(exc))})") from None
    named = [(key, scene.geometry[key]) for key in sorted(scene.geometry, key=_natural_key)]
    named = [(k, m) for k, m in named if isinstance(m, trimesh.Trimesh) and len(m.faces)]
    parts = [m for _, m in named]
    if not parts:
        raise ModelFileError(path, "the file has no faces")
    mesh = cast(trimesh.Trimesh, trimesh.util.concatenate(parts))  # meshes join to a mesh
    if not np.isfinite(mesh.vertices).all():
        raise ModelFileError(path, "a vertex has a coordinate that is not a finite number")
    lo, hi = mesh.bounds
    offset = -np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2])
    if np.any(offset != 0):
        move = trimesh.transformations.translation_matrix(offset)
        parts = [p.copy().apply_transform(move) for p in parts]
        mesh = mesh.copy().apply_transform(move)
    extents = mesh.extents
    size = (float(extents[0]), float(extents[1]), float(extents[2]))
    if min(size) <= 0:
        raise ModelFileError(path, f"the model is flat (size {size[0]:g} × {size[1]:g} × "
                                   f"{size[2]:g} m); every extent must be positive")
    arrays = ModelGeometry(
        vertices=tuple(np.array(p.vertices, dtype=np.float64) for p in parts),
        faces=tuple(np.array(p.faces, dtype=np.int64) for p in parts),
        colors=tuple(_vertex_colors(p) for p in parts),
        size=size, volume=0.0, convex_parts=True, names=tuple(k for k, _ in named))
    rebuilt = arrays.parts
    return replace(arrays, volume=sum(part_volume(p) for p in rebuilt),
                   convex_parts=all(is_convex_part(p) for p in rebuilt))


def _vertex_colors(part: trimesh.Trimesh) -> np.ndarray | None:
    """The part's RGBA vertex colours, or None when the file gave none. Texture
    coordinates are not kept: no texture is ever read (see :func:`_obj_text`)."""
    visual = part.visual
    if visual is None or visual.kind != "vertex":
        return None
    return np.array(getattr(visual, "vertex_colors"), dtype=np.uint8)


def _obj_text(path: Path, data: bytes) -> str:
    """The OBJ file's bytes ``data`` as text: UTF-8 (a byte-order mark is dropped), any
    line ending, within :data:`MAX_MODEL_VERTICES`.

    Reading the text here, rather than letting trimesh open the file, keeps its encoding
    guess (``charset_normalizer``) from failing on bytes that are not text and keeps it
    from opening the material libraries a file names (``mtllib``), which could lie
    outside the sandbox; models take their colours from vertex colours and ``# color``.

    Raises
    ------
    ModelFileError
        The file is not UTF-8 text outside comments (naming the line and column), has
        too many vertices, faces or parts, or a face corner names no vertex defined
        before it (naming the line).
    """
    text = _decode_obj(path, data).replace("\r\n", "\n").replace("\r", "\n")
    vertices = len(_VERTEX_LINE.findall(text))
    faces = len(_FACE_LINE.findall(text))
    if vertices > MAX_MODEL_VERTICES or faces > 2 * MAX_MODEL_VERTICES:
        raise ModelFileError(path, f"{vertices:,} vertices and {faces:,} faces; a furniture "
                                   f"model may have at most {MAX_MODEL_VERTICES:,} vertices "
                                   f"and {2 * MAX_MODEL_VERTICES:,} faces (docs/limits.md)")
    parts = len(_PART_LINE.findall(text))
    if parts > MAX_MODEL_PARTS:
        raise ModelFileError(path, f"{parts:,} groups or objects; a furniture model may have "
                                   f"at most {MAX_MODEL_PARTS:,} parts (docs/limits.md)")
    _check_face_indices(path, text)
    return text


def _decode_obj(path: Path, data: bytes) -> str:
    """UTF-8 text; a comment line in another encoding (a Latin-1 note from an old
    exporter) is read with its undecodable bytes replaced, since comments carry no
    geometry. Anywhere else such a byte is an error naming its line and column."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        pass
    lines = data.removeprefix(b"\xef\xbb\xbf").split(b"\n")
    out = []
    for number, line in enumerate(lines, start=1):
        try:
            out.append(line.decode("utf-8"))
        except UnicodeDecodeError as exc:
            if line.lstrip().startswith(b"#"):
                out.append(line.decode("utf-8", errors="replace"))
                continue
            raise ModelFileError(path, f"line {number}, column {exc.start + 1}: not UTF-8 text "
                                       f"(byte 0x{line[exc.start]:02x}); save the model as "
                                       f"UTF-8 OBJ") from None
    return "\n".join(out)


def _check_face_indices(path: Path, text: str) -> None:
    """Every face corner names a vertex defined before it (OBJ indices count from 1;
    negative ones count back from the last vertex so far), else an error naming the line."""
    vertices = 0
    for number, line in enumerate(text.split("\n"), start=1):
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            vertices += 1
        elif words[0] == "f":
            for corner in words[1:]:
                field = corner.split("/")[0]
                try:
                    index = int(field)
                except ValueError:
                    raise ModelFileError(path, f"line {number}: face corner {excerpt(corner)} "
                                               f"is not a vertex number") from None
                if not (1 <= index <= vertices or -vertices <= index <= -1):
                    raise ModelFileError(path, f"line {number}: face corner {index} names no "
                                               f"vertex ({vertices} defined before this line)")


def _read_header(path: Path, text: str) -> tuple[float, tuple[float, float, float]]:
    density, color = DEFAULT_DENSITY, DEFAULT_COLOR
    for number, line in enumerate(text.splitlines(), start=1):
        match = _HEADER.match(line.strip())
        if match is None:
            continue
        key, values = match.group(1).lower(), match.group(2).split()
        try:
            numbers = [float(v) for v in values]
        except ValueError:
            numbers = []
        if key == "density":
            if len(numbers) != 1 or not 0 < numbers[0] < math.inf:
                raise ModelFileError(path, f"line {number}: '# density' needs one positive "
                                           f"finite number in kg/m³, got "
                                           f"{excerpt(match.group(2).strip())}")
            density = numbers[0]
        else:
            if len(numbers) != 3 or not all(0 <= c <= 1 for c in numbers):
                raise ModelFileError(path, f"line {number}: '# color' needs three numbers "
                                           f"in 0..1 (r g b), got "
                                           f"{excerpt(match.group(2).strip())}")
            color = (numbers[0], numbers[1], numbers[2])
    return density, color


def _natural_key(name: str) -> list[object]:
    return [(0, int(t)) if t.isdigit() else (1, t) for t in re.split(r"(\d+)", name) if t]


def grammar_model_dirs(grammar_file: Path) -> list[Path]:
    """The folders a grammar's own models live in: its folder and its ``models/`` subfolder."""
    folder = Path(grammar_file).resolve().parent
    return [folder, folder / "models"]


def default_library(extra_dirs: Iterable[Path] = (), sandbox: "Sandbox | None" = None
                    ) -> ModelLibrary:
    """A library searching ``extra_dirs`` (in order) and then the shipped models
    (package ``cga.furniture_models``, found with :func:`cga.resources.shipped_dir`),
    reading only inside ``sandbox`` when one is given."""
    shipped = shipped_dir("cga.furniture_models")
    return ModelLibrary([*map(Path, extra_dirs), *([shipped] if shipped else [])], sandbox)


def grammar_library(grammar_dir: Path | None, sandbox: "Sandbox | None" = None
                    ) -> ModelLibrary:
    """The model library of a build: the grammar's folder and its ``models/``, then each
    folder the user allowed (``--allow-path``) and its ``models/``, then the shipped
    models; reading only inside ``sandbox``."""
    folders = [Path(grammar_dir)] if grammar_dir is not None else []
    if sandbox is not None:
        folders.extend(sandbox.allowed)
    return default_library([d for folder in folders for d in (folder, folder / "models")],
                           sandbox)
