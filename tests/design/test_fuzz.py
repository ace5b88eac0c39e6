"""Fuzz the design loader: any input gives a valid design or a DesignError, never a traceback or NaN."""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath import analytic, design

BASE = design.to_dict(design.preset("paper"))

scalars = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1.0, max_value=1.0),
    st.integers(min_value=-10, max_value=10),
    st.text(max_size=5),
    st.booleans(),
    st.none(),
    st.lists(st.floats(), max_size=3),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
)

paths = [(k, f) for k in ("coil", "tube", "channel", "tip") for f in BASE[k]] + [
    ("materials", m) for m in BASE["materials"]
]


def _copy(d):
    return {k: (_copy(v) if isinstance(v, dict) else v) for k, v in d.items()}


@st.composite
def mutated(draw):
    data = _copy(BASE)
    for _ in range(draw(st.integers(min_value=1, max_value=4))):
        table, key = draw(st.sampled_from(paths))
        action = draw(st.sampled_from(["set", "scale", "delete", "add"]))
        target = data[table] if table != "materials" else data["materials"][key]
        if table == "materials":
            key = draw(st.sampled_from(["youngs_modulus", "poisson_ratio", "yeoh", "name"]))
        if action == "set":
            target[key] = draw(scalars)
        elif action == "scale" and isinstance(target.get(key), float):
            target[key] = target[key] * draw(st.floats(min_value=-3, max_value=3))
        elif action == "delete":
            target.pop(key, None)
        else:
            target[draw(st.text(min_size=1, max_size=4))] = draw(scalars)
    return data


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_loader_never_crashes_and_never_returns_nan(data):
    try:
        d = design.from_dict(data)
    except design.DesignError as exc:
        assert str(exc)  # a message naming the parameter
        return
    r = analytic.response(d, np.array([0.0, 1.0]))
    for v in (r.curvature, r.elongation, r.tip_x, r.tip_y):
        assert np.all(np.isfinite(v))
    assert all(math.isfinite(v) for v in d.section.shape.values())
