"""Fuzzing every kind of input the command line reads (issue 19).

A small valid project — a grammar, a typing table, a furniture table, a model that
shadows a shipped one, a GeoJSON lot — has one of its inputs (or the command line)
replaced by a hypothesis-drawn hostile variant: mutated or random grammar text, tables
with odd cells, rows, headers, encodings and line ends, OBJ files with broken lines,
headers and bytes, arbitrary JSON as a lot, odd option values. ``cga check`` runs on
the grammar, table and model cases (cheap: parse, static checks, tables and models
loaded), ``cga build`` of a small massing grammar on the lot and option cases, and a
full ``cga build --no-physics`` of the furnished project on one case per batch.

The properties, for every case:

* the command returns 0 or 2 — an error in the input is a :class:`~cga.errors.CGAError`
  (or an argparse usage error), never a traceback;
* an error message is short (no input is echoed whole);
* no file outside ``--out`` is created, changed or removed;
* the command finishes: each batch runs in a forked child limited to
  :data:`BATCH_TIME` seconds and 2 GB (``tests/support/forked.py``).

:data:`EXAMPLES` batches of :data:`BATCH` cases make 2,000 cases.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cga.cli import main
from cga.resources import shipped_dir
from forked import run_forked

pytestmark = pytest.mark.slow

RULES = shipped_dir("cga.rules")
MODELS = shipped_dir("cga.furniture_models")
BATCH = 25
EXAMPLES = 80
BATCH_TIME = 90.0
"""Seconds a batch of :data:`BATCH` cases may take in its child (a case takes ~10 ms to
~1 s; the limit only catches hangs)."""
MAX_MESSAGE = 6_000
"""Longest stderr a failing case may print (messages quote short excerpts only)."""

GRAMMAR = """\
units = 1;
Lot: rectangle(9, 7)
Variables:
  wallWidth = 0.2;
  doorWidth = 0.9;
  steps = 10;
Rules:
Lot --> extrude(6) Body
Body --> repeated_split("Y", 3){Storey, Storey}
Storey --> make_floor(2, wallWidth, 1>1.2>1.2, doorWidth, 2.1) Floor
Floor --> type_rooms("types.csv") Typed
Typed --> add_furniture("furniture.csv", wallWidth>1.2>1.2, doorWidth, 2.1, steps, 3) Done
"""
MASSING = "Rules:\nLot --> extrude(6) Body\nBody --> split(\"x\"){ ~3 : Bay }*\n"
LOT = {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]]]}


def _base_files() -> dict[str, bytes]:
    return {
        "g.grammar": GRAMMAR.encode(),
        "types.csv": (RULES / "house_types.csv").read_bytes(),
        "furniture.csv": (RULES / "furniture_house.csv").read_bytes(),
        "sofa.obj": (MODELS / "sofa.obj").read_bytes(),
        "lot.geojson": json.dumps(LOT).encode(),
        "m.grammar": MASSING.encode(),
    }


BASE = _base_files()

# -- strategies ------------------------------------------------------------------------

WEIRD_TEXT = ("", " ", "0", "-1", "-3", "1e-9", "1e300", "1e309", "nan", "inf", "-inf",
              "9" * 400, "\x00", "\x1b[31m", "\r", "\n", "\t", "\ufeff", "\u202e", "é", "☃",
              "..", "../../etc/passwd", "/etc/passwd", "/proc/self/status",
              "..\\..\\x.csv", "D:\\Rooms\\types.csv", "x" * 300, '"', "'", ";", ",",
              "((((((((", "]]]]", "{", "}", "|", "%", "*", "~", "#", "-->", "Rules:",
              "Lot", "case", "else", "true", "split", "[1;2]", "1>2>3")
WEIRD = st.one_of(st.sampled_from(WEIRD_TEXT), st.text(max_size=12))
BYTE_MARKS = (b"\xef\xbb\xbf", b"\r", b"\r\n", b"\x00", b"\xff\xfe", b"\x80", b"\xc3")


@st.composite
def mutated(draw: st.DrawFn, base: bytes) -> bytes:
    """``base`` with a few random edits: text inserted or replaced, slices deleted, bytes
    that are not text, line ends changed, a byte-order mark."""
    data = bytearray(base)
    for _ in range(draw(st.integers(1, 4))):
        position = draw(st.integers(0, len(data)))
        edit = draw(st.sampled_from(("insert", "replace", "delete", "bytes", "line ends")))
        if edit == "insert":
            data[position:position] = draw(WEIRD).encode("utf-8", "surrogatepass")
        elif edit == "replace":
            end = min(len(data), position + draw(st.integers(1, 12)))
            data[position:end] = draw(WEIRD).encode("utf-8", "surrogatepass")
        elif edit == "delete":
            end = min(len(data), position + draw(st.integers(1, 200)))
            del data[position:end]
        elif edit == "bytes":
            data[position:position] = draw(st.sampled_from(BYTE_MARKS))
        else:
            data = bytearray(bytes(data).replace(b"\n", draw(st.sampled_from((b"\r", b"\r\n")))))
    return bytes(data)


def _table_rows(base: bytes) -> st.SearchStrategy[bytes]:
    """Tables whose cells are replaced one by one with odd values."""
    lines = base.decode("utf-8-sig").splitlines()

    @st.composite
    def table(draw: st.DrawFn) -> bytes:
        rows = [line.split(";") for line in lines]
        for _ in range(draw(st.integers(1, 5))):
            row = draw(st.integers(0, len(rows) - 1))
            column = draw(st.integers(0, len(rows[row]) - 1))
            rows[row][column] = draw(WEIRD)
        if draw(st.booleans()):
            rows = rows[:draw(st.integers(0, len(rows)))]
        text = "\n".join(";".join(cells) for cells in rows)
        return text.encode("utf-8", "surrogatepass")
    return table()


OBJ_LINES = st.one_of(
    st.builds(lambda x, y, z: f"v {x} {y} {z}", *[st.sampled_from(
        ("0", "1", "-1", "0.5", "nan", "inf", "1e308", "x", ""))] * 3),
    st.builds(lambda a, b, c: f"f {a} {b} {c}", *[st.sampled_from(
        ("1", "2", "3", "4", "0", "-1", "99", "1/1", "a", ""))] * 3),
    st.sampled_from(("# density 450", "# density inf", "# density -1", "# density nan",
                     "# density", "# color 0.5 0.5 0.5", "# color 2 0 0", "# color x",
                     "g part", "o part", "mtllib ../../../../etc/passwd", "usemtl x",
                     "vt 0 0", "vn 0 1 0", "s off", "")),
    WEIRD)


@st.composite
def obj_files(draw: st.DrawFn) -> bytes:
    if draw(st.booleans()):
        return draw(mutated(BASE["sofa.obj"]))
    lines = draw(st.lists(OBJ_LINES, max_size=30))
    return "\n".join(lines).encode("utf-8", "surrogatepass")


JSON = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=False),
              st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=5),
                            st.dictionaries(st.sampled_from(
                                ("type", "coordinates", "features", "geometry", "x")),
                                inner, max_size=4)),
    max_leaves=20)
POSITION = st.lists(st.one_of(st.integers(-10**6, 10**6), st.floats(-1e6, 1e6),
                              st.sampled_from((1e300, -0.0))), min_size=1, max_size=4)


@st.composite
def geojson_files(draw: st.DrawFn) -> bytes:
    kind = draw(st.sampled_from(("json", "polygon", "feature", "mutated")))
    if kind == "json":
        document = draw(JSON)
    elif kind == "mutated":
        return draw(mutated(BASE["lot.geojson"]))
    else:
        ring = draw(st.lists(POSITION, min_size=0, max_size=8))
        document = {"type": draw(st.sampled_from(("Polygon", "MultiPolygon", "Point"))),
                    "coordinates": draw(st.sampled_from(([ring], ring, [[ring]])))}
        if kind == "feature":
            document = {"type": "FeatureCollection",
                        "features": draw(st.sampled_from(([{"type": "Feature",
                                                            "geometry": document}],
                                                          5, None, [document])))}
    return json.dumps(document).encode()


OPTION_VALUES = {
    "--seed": ("0", "-1", "1e12", "x", "99999999999999999999"),
    "--lot": ("14x10", "0x5", "1e6x1e6", "99999x99999", "polygon((0,0),(1,1),(0,1),(1,0))",
              "lot.geojson", "missing.geojson", "../lot.geojson", "/etc/passwd", "x" * 500),
    "--units": ("0", "-1", "nan", "1e-9", "1e9", "x"),
    "--robot-radius": ("0", "1e6", "nan", "-1", "0.3"),
    "--max-depth": ("0", "1", "100000", "-5", "x"),
    "--export": ("foo", "map", "obj,urdf", ",,,", "plan,plan"),
    "--allow-path": ("/etc", "nonexistent", ".", "..", "\x00"),
}


@st.composite
def argv_variants(draw: st.DrawFn) -> list[str]:
    options = draw(st.lists(st.sampled_from(sorted(OPTION_VALUES)), max_size=3, unique=True))
    argv: list[str] = []
    for option in options:
        argv += [option, draw(st.sampled_from(OPTION_VALUES[option]))]
    return argv


@st.composite
def cases(draw: st.DrawFn) -> tuple[str, dict[str, bytes], list[str]]:
    """(input kind, the project's files, extra options) with one input made hostile."""
    files = dict(BASE)
    kind = draw(st.sampled_from(("grammar", "grammar text", "typing table", "furniture table",
                                 "model", "lot", "options")))
    argv: list[str] = []
    if kind == "grammar":
        files["g.grammar"] = draw(mutated(BASE["g.grammar"]))
    elif kind == "grammar text":
        files["g.grammar"] = draw(st.text(max_size=300)).encode("utf-8", "surrogatepass")
    elif kind == "typing table":
        files["types.csv"] = draw(st.one_of(_table_rows(BASE["types.csv"]),
                                            mutated(BASE["types.csv"])))
    elif kind == "furniture table":
        files["furniture.csv"] = draw(st.one_of(_table_rows(BASE["furniture.csv"]),
                                                mutated(BASE["furniture.csv"])))
    elif kind == "model":
        files["sofa.obj"] = draw(obj_files())
    elif kind == "lot":
        files["lot.geojson"] = draw(geojson_files())
        argv = ["--lot", "lot.geojson"]
    else:
        argv = draw(argv_variants())
    return kind, files, argv


# -- running a batch in a child -----------------------------------------------------------

def _snapshot(folder: Path, out: Path) -> dict[str, tuple[int, int]]:
    """Every file under ``folder`` but outside ``out``: size and modification time."""
    found = {}
    for root, dirs, names in os.walk(folder):
        if Path(root) == out.parent and out.name in dirs:
            dirs.remove(out.name)
        for name in names:
            path = Path(root, name)
            stat = path.lstat()
            found[str(path.relative_to(folder))] = (stat.st_size, stat.st_mtime_ns)
    return found


def _run_case(folder: Path, files: dict[str, bytes], argv: list[str], build: bool) -> str | None:
    """One case in ``folder``; a description of what went wrong, or None."""
    folder.mkdir()
    for name, data in files.items():
        (folder / name).write_bytes(data)
    before = _snapshot(folder.parent, folder / "out")
    if build:
        command = ["build", "g.grammar", "--no-physics", "--quiet", "--out", "out", *argv]
    elif argv:  # lot and option cases: the massing grammar builds in milliseconds
        command = ["build", "m.grammar", "--no-physics", "--quiet", "--out", "out", *argv]
    else:
        command = ["check", "g.grammar"]
    err = io.StringIO()
    previous = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                status = main(command)
            except SystemExit as exit_:  # argparse usage errors
                status = exit_.code if isinstance(exit_.code, int) else 2
    finally:
        os.chdir(previous)
    text = err.getvalue()
    if status not in (0, 2):
        return f"exit status {status}: {text[:2000]}"
    if "Traceback" in text:
        return f"a traceback: {text[:2000]}"
    if len(text) > MAX_MESSAGE:
        return f"{len(text):,} characters on stderr: {text[:300]}"
    if status == 2 and not text.strip():
        return "exit status 2 without a message"
    after = _snapshot(folder.parent, folder / "out")
    if after != before:
        changed = sorted(set(after.items()) ^ set(before.items()))
        return f"files outside --out changed: {changed[:5]}"
    return None


def _run_batch(batch: list[tuple[str, dict[str, bytes], list[str]]]) -> list[str]:
    """Every case of a batch in its own folder; the problems found (empty: none)."""
    problems = []
    with tempfile.TemporaryDirectory(prefix="cga-fuzz-") as root:
        for index, (kind, files, argv) in enumerate(batch):
            case_root = Path(root, f"case{index}")
            case_root.mkdir()
            try:
                problem = _run_case(case_root / "project", files, argv, build=index == 0)
            except Exception as error:  # noqa: BLE001 - reported as the case's bug
                problem = f"{type(error).__name__}: {error}"[:2000]
            if problem is not None:
                problems.append(f"case {index} ({kind}, {argv}): {problem}")
            shutil.rmtree(case_root, ignore_errors=True)
    return problems


@pytest.fixture(scope="module", autouse=True)
def warm_caches(tmp_path_factory):
    """Check the base project once in this process: forked children inherit its parsed
    grammar machinery, tables and models."""
    assert _run_batch([("base", BASE, [])]) == []


@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                 HealthCheck.large_base_example])
@given(batch=st.lists(cases(), min_size=BATCH, max_size=BATCH))
def test_every_input_kind_is_read_or_refused_cleanly(batch):
    status, value = run_forked(_run_batch, batch, time_limit=BATCH_TIME)
    assert status != "timeout", f"a batch did not finish within {BATCH_TIME:g} s: " + \
        "; ".join(f"{kind} {argv}" for kind, _, argv in batch)
    assert status == "ok", value
    assert value == [], "\n".join(value)
