"""What an operation is: a declared signature and an ``apply`` that makes child shapes.

The evaluator binds a call's arguments against :attr:`Operation.params` (positional or
keyword), checks their kinds, converts lengths and areas from grammar units to metres,
and hands the result to :meth:`Operation.apply` as a plain dict. The operation returns
:class:`Child` records; the evaluator names them after the successors and builds the
shapes, so operations never deal with paths, symbols or random-stream bookkeeping.

Parameter kinds (``Param.kind``):

``length``  number in grammar units, converted to metres
``area``    number in grammar units², converted to m²
``number``  plain number;  ``count``: non-negative integer;  ``bool``: true/false/0/1
``string``  quoted string; ``path``: string resolved by :meth:`OperationContext.resolve`
``axis``    one of "x", "y", "z" (case-insensitive)
``tuple``   ``a>b>c`` or ``(a, b, c)``; ``Param.items`` gives each element's kind
``range``   a pair ``(lo, hi)`` of plain numbers, e.g. ``cut_range=(0.35, 0.65)``
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Literal

import numpy as np

from cga.errors import Span
from cga.model import Diagnostic
from cga.shape import Geometry, Scope

if TYPE_CHECKING:  # pragma: no cover
    from cga.model import FloorPlan
    from cga.operations.furniture.library import ModelLibrary
    from cga.sandbox import Sandbox
    from cga.shape import Shape

__all__ = ["REQUIRED", "ParamKind", "Param", "Child", "OperationContext", "CheckContext",
           "Operation", "PARALLEL_SPINES_USED", "is_number"]

ParamKind = Literal["length", "area", "number", "count", "bool", "string", "path", "axis",
                    "tuple", "range"]
"""The kinds of operation parameters (the table above); :mod:`cga.binding` converts each."""


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()
"""Default marker of a parameter that must be given."""


@dataclass(frozen=True)
class Param:
    """One parameter of an operation's signature."""

    name: str
    kind: ParamKind
    default: Any = REQUIRED
    items: tuple[ParamKind, ...] = ()
    keyword_only: bool = False
    doc: str = ""

    @property
    def required(self) -> bool:
        return self.default is REQUIRED


@dataclass(frozen=True)
class Child:
    """A shape an operation produced, bound for successor number ``successor``.

    ``attrs`` are merged into the parent's attributes (e.g. ``{"floor": 1}`` or
    ``{"index": 3}``); ``plan`` carries a floor plan from the floor operations.
    """

    successor: int
    geometry: Geometry
    scope: Scope
    attrs: dict[str, Any] = field(default_factory=dict)
    plan: "FloorPlan | None" = None


@dataclass
class OperationContext:
    """What an operation may use besides its arguments.

    ``rng`` is this shape's own random stream (derived from the seed and the shape's
    path), ``units`` the grammar's metres per unit, ``resolve`` finds a path argument
    (next to the grammar, then in the shipped ``rules/``), ``report`` records a
    diagnostic for the summary, ``span`` is the call's position for error messages and
    ``cache`` is shared by all operations of one build (models are loaded once).
    ``seed`` is the build seed, for operations that want the same draw on every shape
    (``make_floor(..., same_layout=true)``). ``strict`` is the build's strict mode: an
    operation that would repair a problem and report it (e.g. add a door so every room
    is reachable) fails instead. ``base_dir`` is the grammar's folder (None when the
    grammar has no file), where a grammar keeps its own furniture models. ``library`` is
    the build's furniture model library, shared with the meshing layer so each model is
    loaded once per build (None in a hand-made context: ``add_furniture`` then makes one
    from ``base_dir``). ``sandbox`` holds the folders files may be read from
    (:mod:`cga.sandbox`); None reads any. ``shapes_left`` is how many more shapes the
    derivation may make (:data:`cga.evaluator.MAX_SHAPES`); an operation that can tell in
    advance that it would make more refuses. ``parallel_spines`` says whether
    ``make_floor`` may lay a floor too deep for one corridor on parallel spines (its
    ``max_room_depth``); one that does notes it in ``cache`` under
    :data:`PARALLEL_SPINES_USED`, and the evaluator derives a grammar whose rooms then
    cannot be typed once more without them (:meth:`cga.evaluator.Evaluator.derive`).
    """

    rng: np.random.Generator
    units: float
    resolve: Callable[[str, str], Any]
    report: Callable[[Diagnostic], None]
    span: Span | None
    successor_count: int
    cache: dict[str, Any] = field(default_factory=dict)
    seed: int = 0
    strict: bool = False
    base_dir: Path | None = None
    library: "ModelLibrary | None" = None
    sandbox: "Sandbox | None" = None
    shapes_left: int | None = None
    parallel_spines: bool = True


PARALLEL_SPINES_USED = "make_floor: parallel spines"
"""The :attr:`OperationContext.cache` key an operation sets when it laid a floor on
parallel spines (see :class:`OperationContext`)."""


@dataclass
class CheckContext:
    """What :meth:`Operation.check_files` may use in ``cga check`` (no shape, no random
    stream): ``units``, ``resolve`` as in :class:`OperationContext`, the grammar's folder,
    the sandbox and a cache shared by all checks of one grammar."""

    units: float
    resolve: Callable[[str, str], Any]
    base_dir: Path | None = None
    sandbox: "Sandbox | None" = None
    cache: dict[str, Any] = field(default_factory=dict)
    library: "ModelLibrary | None" = None


def is_number(value: Any) -> bool:
    """Whether ``value`` is a known number (not a bool, not ``UNKNOWN`` in a static check)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Operation:
    """Base class of grammar operations.

    Subclasses set ``name``, ``params``, the accepted successor counts and implement
    :meth:`apply`. ``min_successors``/``max_successors`` let the evaluator report a
    successor-count mismatch at the rule instead of deep inside the operation
    (``max_successors=None`` means any number).
    """

    name: ClassVar[str]
    params: ClassVar[tuple[Param, ...]] = ()
    min_successors: ClassVar[int] = 1
    max_successors: ClassVar[int | None] = 1
    takes_split_parts: ClassVar[bool] = False
    doc: ClassVar[str] = ""

    def apply(self, shape: "Shape", args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        raise NotImplementedError

    def check_values(self, args: dict[str, Any], units: float) -> None:
        """Refuse argument values that no shape could accept (a negative height, a zero
        wall width), raising :class:`~cga.errors.DerivationError`.

        ``apply`` calls it first; ``cga check`` calls it without geometry, so a value may
        be :data:`~cga.expressions.UNKNOWN` (it depends on the shape) and is then
        skipped (:func:`is_number`). The default accepts everything.
        """

    def check_files(self, args: dict[str, Any], ctx: CheckContext) -> None:
        """Load the files the arguments name (rule tables, models) as a build would, for
        ``cga check``; raise the error the build would raise. The default does nothing."""

    def signature(self) -> str:
        """Human-readable signature for error messages, e.g. ``extrude(height)``."""
        parts = []
        for p in self.params:
            text = p.name if p.required else f"{p.name}={p.default!r}"
            parts.append(text)
        return f"{self.name}({', '.join(parts)})"
