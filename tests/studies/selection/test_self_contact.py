"""A design bending past a full turn passes through itself (no tier models it): select removes it,
optimise never returns it, and the reason is said."""

from __future__ import annotations

import json
from typing import cast

import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from softcath.studies.model_validity import fail_self_contact, self_contact_reasons


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(angles=st.lists(st.lists(st.floats(-1000, 1000), min_size=1, max_size=4), min_size=1, max_size=5))
def test_exactly_the_designs_past_a_turn_are_failed_with_their_reason(angles):
    rows = [
        {"design_id": d, "pressure_MPa": 0.1 * k, "bend_angle_deg": a, "status": "ok", "reason": ""}
        for d, series in enumerate(angles)
        for k, a in enumerate(series)
    ]
    df = pd.DataFrame(rows)
    out = fail_self_contact(df)
    past = {d for d, series in enumerate(angles) if any(abs(a) > 360 for a in series)}
    assert set(self_contact_reasons(df)) == past
    assert set(out.loc[out["status"] == "failed", "design_id"]) == past
    assert all("passes through itself" in r for r in out.loc[out["status"] == "failed", "reason"])
    assert cast(bool, (df["status"] == "ok").all())  # the input is not changed


def test_select_and_optimise_leave_out_a_tip_through_itself(cli, spec_writer, tmp_path):
    spec = spec_writer(
        """
        [sweep]
        base = "paper"
        pressures_MPa = [0.0, 5.0, 15.0]
        evaluators = ["paper"]
        [parameters]
        "tube.h" = { values = [0.0, 0.02] }
        "tip.bending_length" = { values = [2.0, 5.0] }
        """
    )
    assert cli("sweep", spec, "--out", tmp_path / "s", "--workers", "1", "--no-progress").status == 0
    r = cli("select", tmp_path / "s", "--objective", "maximise bend_angle_deg at p=5")
    assert r.status == 0 and "removed 2: bend past 360 deg" in r.out
    argv = ["optimise", "paper", "--model", "paper", "--vary", "tip.bending_length=2:6", "--no-fem-check"]
    r = cli(*argv, "--objective", "maximise bend_angle_deg at p=15", "--no-progress", "--out", tmp_path / "o")
    assert r.status == 0, r.err
    best = json.loads((tmp_path / "o" / "optimum.json").read_text())["best"][0]
    assert best["objectives"]["maximise bend_angle_deg at p=15"] <= 360
