"""Grammar-variable overrides: ``cga build house.grammar --set difficulty=7``.

A grammar's ``Variables:`` section names the knobs of a building; ``--set NAME=VALUE``
(``cga build`` and ``cga batch``) replaces a variable's value without editing the file,
and ``cga batch --sweep NAME=LO:HI`` builds every value of a range (docs/difficulty.md,
"Sweeps"). The value must be of the kind the grammar's own value has: a number for a
number (``7``, ``2.5``, ``1e3``), ``true``/``false`` for a truth value, any text for a
string; a name the grammar does not declare is an error that lists the declared names.
Later variables that use the overridden one see the new value.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping, Sequence

from .ast import Grammar
from .errors import UsageError
from .expressions import Value, describe

__all__ = ["parse_assignments", "check_override_names", "override_value", "parse_sweep"]

MAX_SWEEP_VALUES = 1000
"""Most values one ``--sweep`` may ask for."""


def parse_assignments(items: Sequence[str], option: str = "--set") -> dict[str, str]:
    """``["difficulty=7", "tries=5"]`` → ``{"difficulty": "7", "tries": "5"}``.

    Raises
    ------
    UsageError
        An item without ``=`` or with an empty name; a name given twice.
    """
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UsageError(f"{option} expects NAME=VALUE, got {item!r}")
        if name in out:
            raise UsageError(f"{option} sets {name!r} twice")
        out[name] = value.strip()
    return out


def check_override_names(grammar: Grammar, names: Sequence[str] | Mapping[str, object],
                         option: str = "--set") -> None:
    """Raise :class:`UsageError` for a name the grammar's ``Variables:`` do not declare."""
    declared = [a.name for a in grammar.variables]
    for name in names:
        if name in declared:
            continue
        close = difflib.get_close_matches(name, declared, n=1)
        hint = (f"; did you mean {close[0]!r}?" if close else
                f"; it declares {', '.join(declared)}" if declared else
                "; it has no Variables: section")
        raise UsageError(f"{option} {name}: the grammar {grammar.file} has no variable "
                         f"{name!r}{hint}")


def override_value(name: str, text: str, current: Value, option: str = "--set") -> Value:
    """The override ``text`` as a value of the kind of ``current`` (the grammar's value).

    Raises
    ------
    UsageError
        ``text`` is not of that kind, or the variable is a tuple (not overridable).
    """
    if isinstance(current, bool):
        lowered = text.lower()
        if lowered in ("true", "1"):
            return True
        if lowered in ("false", "0"):
            return False
        raise UsageError(f"{option} {name}={text}: {name} is a truth value "
                         f"(the grammar gives {describe(current)}); write true or false")
    if isinstance(current, float):
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise UsageError(f"{option} {name}={text}: {name} is a number (the grammar "
                             f"gives {describe(current)}); write a finite number such as 7 or 2.5")
        return value
    if isinstance(current, str):
        return text
    raise UsageError(f"{option} {name}: {name} is {describe(current)}, which cannot be "
                     f"set from the command line (numbers, truth values and strings can)")


def parse_sweep(text: str) -> tuple[str, list[float]]:
    """``difficulty=0:10`` → ``("difficulty", [0, 1, ..., 10])``; ``x=0:1:0.25`` steps by
    0.25; ``x=1,3,5`` lists values. Both ends of a range are included.

    Raises
    ------
    UsageError
        Not ``NAME=LO:HI[:STEP]`` or ``NAME=A,B,...``; a step that is not positive; more
        than :data:`MAX_SWEEP_VALUES` values.
    """
    name, value = next(iter(parse_assignments([text], "--sweep").items()))
    try:
        if ":" in value:
            parts = [float(p) for p in value.split(":")]
            if len(parts) not in (2, 3):
                raise ValueError
            lo, hi = parts[0], parts[1]
            step = parts[2] if len(parts) == 3 else 1.0
            if not (math.isfinite(lo) and math.isfinite(hi) and math.isfinite(step)) or step <= 0:
                raise UsageError(f"--sweep {text}: the step must be a positive number")
            if hi < lo:
                raise UsageError(f"--sweep {text}: the range ends below its start")
            count = math.floor((hi - lo) / step + 1e-9) + 1
            if count > MAX_SWEEP_VALUES:
                raise UsageError(f"--sweep {text}: {count} values, at most {MAX_SWEEP_VALUES}")
            values = [round(lo + i * step, 9) for i in range(count)]
        else:
            values = [float(p) for p in value.split(",")]
            if not all(math.isfinite(v) for v in values):
                raise ValueError
    except ValueError:
        raise UsageError(f"--sweep expects NAME=LO:HI, NAME=LO:HI:STEP or NAME=A,B,...; "
                         f"got {text!r}") from None
    return name, values
