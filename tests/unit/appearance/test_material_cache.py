"""A material works its hash and linear colour out once, with the values and equality the
dataclass gave before (issue #21)."""

from __future__ import annotations

import pickle

from hypothesis import given, settings
from hypothesis import strategies as st

from cga.appearance.material import Material, srgb_to_linear

UNIT = st.floats(0.0, 1.0, allow_nan=False)


def _material(color, alpha) -> Material:
    return Material.of("wall", "wall", color, 0.5, 0.0, alpha)


def _old_linear_rgba(m: Material) -> list[float]:
    r, g, b = (float(v) for v in srgb_to_linear(m.color))
    return [round(r, 6), round(g, 6), round(b, 6), m.alpha]


@settings(max_examples=200, deadline=None)
@given(color=st.tuples(UNIT, UNIT, UNIT), alpha=UNIT)
def test_linear_rgba_and_hash_as_before(color, alpha):
    m = _material(color, alpha)
    first = m.linear_rgba()
    assert [v.hex() for v in first] == [float(v).hex() for v in _old_linear_rgba(m)]
    first.append(0.0)  # each call gets its own list
    assert m.linear_rgba() == _old_linear_rgba(m)
    assert hash(m) == hash((m.name, m.row, m.surface, m.color, m.roughness, m.metallic,
                            m.alpha))


def test_equality_and_pickling_keep_the_fields_semantics():
    a, b = _material((0.2, 0.3, 0.4), 1.0), _material((0.2, 0.3, 0.4), 1.0)
    a.linear_rgba()
    assert a == b and hash(a) == hash(b) and a != _material((0.2, 0.3, 0.5), 1.0)
    copy = pickle.loads(pickle.dumps(a))
    assert copy == a and hash(copy) == hash(a) and {a: 1}[copy] == 1
    assert "_hash" not in a.__getstate__()
