"""Every loop a user can size is estimated before it starts: refused above the documented two hours,
said with its estimate above a minute (``fem.limits.check_work_seconds``)."""

from __future__ import annotations

import logging
import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.design.errors import DesignError
from softcath.fem.limits import (
    MAX_WORK_SECONDS,
    WARN_WORK_SECONDS,
    check_work_seconds,
    estimate_finite_strain_seconds,
)


@settings(
    max_examples=100,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(seconds=st.floats(0, 1e9, allow_nan=False) | st.just(float("nan")) | st.just(float("inf")))
def test_the_work_rule(seconds, caplog):
    caplog.clear()
    with caplog.at_level(logging.WARNING):
        if not seconds <= MAX_WORK_SECONDS:
            with pytest.raises(DesignError, match=r"--n = 7: the loop is estimated at .* above the 2 h"):
                check_work_seconds(seconds, param="--n", value=7, what="the loop", hint="less")
        else:
            assert check_work_seconds(seconds, param="--n", value=7, what="the loop", hint="less") == seconds
            assert ("estimated" in caplog.text) == (seconds > WARN_WORK_SECONDS)


@settings(max_examples=50, deadline=None, derandomize=True, database=None)
@given(dofs=st.floats(1e3, 1e6), n=st.integers(1, 10**6))
def test_the_curve_estimate_grows_with_pressures_and_dofs(dofs, n):
    t = estimate_finite_strain_seconds(dofs, n)
    assert estimate_finite_strain_seconds(dofs, n + 1) > t > 0
    assert estimate_finite_strain_seconds(dofs * 2, n) > t


def test_predict_refuses_curve_samples_beyond_the_limit_before_any_work(cli, tmp_path):
    pressures = ",".join(f"{0.1 * k:.1f}" for k in range(1, 11))
    t0 = time.perf_counter()
    argv = ["predict", "paper", "--nonlinear", "--curve-samples", "2000", "--pressures", pressures]
    line = cli(*argv, "--out", tmp_path / "o").error_line()
    assert time.perf_counter() - t0 < 10
    assert "--curve-samples = 2000: 2000 finite-strain curves through 10 pressures is estimated at" in line
    assert not (tmp_path / "o").exists()


def test_a_long_coil_bound_curve_is_said_before_it_starts(cli, tmp_path, caplog):
    """10^6 pressures of the bilinear curve take about two minutes: the estimate comes first."""
    import logging

    from softcath.cli.section import _BILINEAR_SECONDS, _BILINEAR_SECONDS_PER_PRESSURE

    assert _BILINEAR_SECONDS + _BILINEAR_SECONDS_PER_PRESSURE * 10**6 > WARN_WORK_SECONDS
    caplog.set_level(logging.WARNING)
    r = cli("section", "paper", "--coil-bound", "--pressure", "0:1:2", "--no-png", "--out", tmp_path / "o")
    assert r.status == 0 and "estimated" not in r.err + caplog.text  # short curves say nothing
