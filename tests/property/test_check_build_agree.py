"""Rule tables and models mutated into the mistakes users make: ``cga check`` and
``cga build`` agree, and a failed build leaves nothing behind (issue 20).

A small furnished project (one storey: typing table, furniture table, a model that
shadows the shipped sofa) has its typing table, furniture table or model edited the way
people get them wrong: a misspelt type, neighbour or model name, a boolean written
``flase`` or ``yes``, a negative or absurd number, an emptied cell, a face corner that
names no vertex, a Latin-1 comment or group name, a dropped line, a flattened model.
For each case, in a forked child (``tests/support/forked.py``):

* ``check_file`` and ``build`` raise only :class:`~cga.errors.CGAError` subclasses,
  never anything else;
* what the build cannot read (a :class:`~cga.errors.RuleTableError` or
  :class:`~cga.operations.furniture.library.ModelFileError`), ``cga check`` reports
  too, with the same message: the check reads everything a build reads;
* a failed build leaves its output folder exactly as the previous good build left it
  (same files, same bytes), and a build that succeeds leaves no staging folder.

Tens of cases, about 0.5 s each: the build is one storey without physics.
"""

from __future__ import annotations

import hashlib
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cga.errors import CGAError, RuleTableError
from cga.operations.furniture.library import ModelFileError
from cga.pipeline import build
from cga.resources import shipped_dir
from cga.validate import check_file
from forked import run_forked

RULES = shipped_dir("cga.rules")
MODELS = shipped_dir("cga.furniture_models")
EXAMPLES = 30

GRAMMAR = """\
units = 1;
Lot: rectangle(10, 8)
Rules:
Lot --> extrude(3) Storey
Storey --> make_floor(5, 0.2, 1>1.2>1.2, 0.9, 2.1, corridor = "spine", corridor_width = 1.6, min_room_width = 2, min_room_area = 4) Floor
Floor --> type_rooms("types.csv") Typed
Typed --> add_furniture("furniture.csv", 0.2>1.2>1.2, 0.9, 2.1, 10, 3) Done
"""
BASE = {
    "g.grammar": GRAMMAR.encode(),
    "types.csv": (RULES / "house_types.csv").read_bytes(),
    "furniture.csv": (RULES / "furniture_house.csv").read_bytes(),
    "sofa.obj": (MODELS / "sofa.obj").read_bytes(),
}
READING_ERRORS = (RuleTableError, ModelFileError)

# -- the mistakes -----------------------------------------------------------------------

CELL_VALUES = ("", "flase", "yes", "TRUE", "1", "0", "-1", "0.0", "1e9", "nan", "inf",
               "Kitchn", "Livingroom", "Hall, Bedrom", "Hall,,Kitchen", "grandpiano",
               "sofa", "Sofa ", "sofaa", "tvboard", "0.5", "-0.3", "Bathroom;Kitchen")


def _typo(word: str, cut: int) -> str:
    return word[:cut] + word[cut + 1:] if len(word) > 1 else word + "x"


@st.composite
def edited_table(draw: st.DrawFn, base: bytes) -> bytes:
    """``base`` with one to three cells changed: a listed mistake or a typo of the cell."""
    rows = [line.split(";") for line in base.decode("utf-8").splitlines()]
    for _ in range(draw(st.integers(1, 3))):
        row = draw(st.integers(0, len(rows) - 1))
        column = draw(st.integers(0, len(rows[row]) - 1))
        cell = rows[row][column]
        rows[row][column] = (_typo(cell, draw(st.integers(0, max(len(cell) - 1, 0))))
                             if draw(st.booleans()) else draw(st.sampled_from(CELL_VALUES)))
    return ("\n".join(";".join(cells) for cells in rows) + "\n").encode("utf-8")


@st.composite
def edited_model(draw: st.DrawFn) -> bytes:
    lines = BASE["sofa.obj"].split(b"\n")
    faces = [i for i, line in enumerate(lines) if line.startswith(b"f ")]
    vertices = sum(line.startswith(b"v ") for line in lines)
    for _ in range(draw(st.integers(1, 2))):
        edit = draw(st.sampled_from(("face index", "latin-1 comment", "latin-1 group",
                                     "drop line", "flatten", "density", "one group")))
        if edit == "face index":
            k = draw(st.sampled_from(faces))
            bad = draw(st.sampled_from((0, vertices + 1, -vertices - 1, 10**9)))
            lines[k] = b"f 1 2 " + str(bad).encode()
        elif edit == "latin-1 comment":
            lines.insert(draw(st.integers(0, len(lines))), "# Sofa für 3 Personen".encode("latin-1"))
        elif edit == "latin-1 group":
            lines.insert(draw(st.integers(0, len(lines))), "g Rückenlehne".encode("latin-1"))
        elif edit == "drop line":
            del lines[draw(st.integers(0, len(lines) - 1))]
        elif edit == "flatten":
            lines = [b"v %s 0 %s" % tuple(line.split()[1:4:2]) if line.startswith(b"v ") else line
                     for line in lines]
        elif edit == "density":
            lines.insert(0, draw(st.sampled_from((b"# density -1", b"# density nan",
                                                  b"# density 0", b"# density x"))))
        else:
            lines = [line for line in lines if not line.startswith((b"g ", b"o "))]
    return b"\n".join(lines)


@st.composite
def projects(draw: st.DrawFn) -> tuple[str, dict[str, bytes]]:
    files = dict(BASE)
    kind = draw(st.sampled_from(("types.csv", "furniture.csv", "sofa.obj")))
    files[kind] = draw(edited_model() if kind == "sofa.obj" else edited_table(BASE[kind]))
    return kind, files


# -- one case -----------------------------------------------------------------------------

def _contents(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _case(files: dict[str, bytes], good_out: Path) -> list[str]:
    """The problems of one case (empty: none)."""
    problems = []
    with tempfile.TemporaryDirectory(prefix="cga-agree-") as root:
        folder = Path(root)
        for name, data in files.items():
            (folder / name).write_bytes(data)
        out = folder / "out"
        shutil.copytree(good_out, out)
        before = _contents(out)
        try:
            checked = check_file(folder / "g.grammar")
        except CGAError as error:
            checked = [error]
        except Exception as error:  # noqa: BLE001 - the property: only the project's errors
            return [f"check raised {type(error).__name__}: {error}"]
        try:
            build(folder / "g.grammar", seed=0, out_dir=out, formats=("glb", "json"),
                  physics=False, quiet=True)
            failure = None
        except CGAError as error:
            failure = error
        except Exception as error:  # noqa: BLE001
            return [f"build raised {type(error).__name__}: {error}"]
        if failure is None:
            if any(p.name.startswith(".cga-staging") for p in out.iterdir()):
                problems.append("a staging folder was left in the output folder")
        else:
            if _contents(out) != before:
                problems.append(f"the failed build changed the output folder: {failure}")
            if isinstance(failure, READING_ERRORS):
                messages = [str(p).splitlines()[0] for p in checked]
                if str(failure).splitlines()[0] not in messages:
                    problems.append(f"build could not read an input that check passed: "
                                    f"{failure!s:.300} (check said {messages!s:.300})")
    return problems


@pytest.fixture(scope="module")
def good_out(tmp_path_factory) -> Path:
    """The output folder of the unedited project (a failed build must leave it as is);
    building it also warms the caches the forked children inherit."""
    folder = tmp_path_factory.mktemp("good")
    for name, data in BASE.items():
        (folder / name).write_bytes(data)
    assert check_file(folder / "g.grammar") == []
    build(folder / "g.grammar", seed=0, out_dir=folder / "out", formats=("glb", "json"),
          physics=False, quiet=True)
    return folder / "out"


@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(project=projects())
def test_check_and_build_agree_and_a_failed_build_writes_nothing(project, good_out):
    kind, files = project
    status, value = run_forked(_case, files, good_out, time_limit=60.0)
    assert status == "ok", f"{kind}: {status}\n{value}"
    assert value == [], f"{kind}:\n" + "\n".join(value)
