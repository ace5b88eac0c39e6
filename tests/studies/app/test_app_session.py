"""One app session without a browser: background work (newest wins), curves, numbers, uploads, exports."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest

from softcath import analytic, design
from softcath.design.errors import DataError
from softcath.studies.app.curves import formula_curve, linear_section_curve
from softcath.studies.app.export import CSV_COLUMNS, curves_csv, design_toml, view_png
from softcath.studies.app.jobs import LatestJob
from softcath.studies.app.measured import MAX_UPLOAD_BYTES, read_upload
from softcath.studies.app.numbers import design_numbers
from softcath.studies.app.page import Session, finite_strain_work
from softcath.studies.app.server import view
from tests.studies.app import _targets

PAPER_SINE = Path(__file__).resolve().parents[3] / "studies" / "data" / "paper_sine.csv"


def test_a_newer_finite_strain_request_supersedes_the_running_one():
    """Real finite-strain curves in the worker process: the first stops at its next pressure, the
    second never starts, only the third finishes."""
    job = LatestJob(finite_strain_work)
    p = np.linspace(0.0, 1.0, 9)
    paper = design.preset("paper")
    try:
        first = job.submit(paper, p, 0, 0.0)
        end = time.monotonic() + 120
        while first.done < 1 and time.monotonic() < end:  # running, one pressure done
            job.poll()
            time.sleep(0.01)
        queued = job.submit(paper, p, 1, 0.0)
        last = job.submit(paper.with_tube_shape(a=0.2, a_int=0.1, b_int=0.07, h=0.0), p, 2, 0.0)
        assert job.wait(last, 120) and job.wait(first, 5) and job.wait(queued, 5)
        assert (first.state, queued.state, last.state) == ("cancelled", "cancelled", "done")
        assert 1 <= first.done < first.total  # stopped before its last pressure
        assert queued.done == 0  # never started
        version, curve = last.result
        assert job.latest is last and version == 2 and curve.pressure_MPa.size == p.size
    finally:
        job.close()


def test_a_waiting_request_is_superseded_and_failures_stay_in_their_ticket():
    job = LatestJob(_targets.wait_for)
    try:
        waiting = job.submit(30.0)
        end = time.monotonic() + 60
        while waiting.state != "running" and time.monotonic() < end:
            job.poll()
            time.sleep(0.02)
        newer = job.submit(0.1)
        assert job.wait(newer, 25) and job.wait(waiting, 1)  # well before the 30 s wait would end
        assert waiting.state == "cancelled" and newer.result == "waited"
    finally:
        job.close()
    job = LatestJob(_targets.divide)
    try:
        bad = job.submit(0.0)
        assert job.wait(bad, 60) and bad.state == "failed"
        assert bad.message.startswith("unexpected ZeroDivisionError")
        good = job.submit(4.0)
        assert job.wait(good, 10) and (good.state, good.result) == ("done", 0.25)
    finally:
        job.close()


def test_a_worker_that_dies_fails_its_request_and_is_started_again():
    job = LatestJob(_targets.die)
    try:
        dead = job.submit(3)
        assert job.wait(dead, 60)
        assert dead.state == "failed" and "exit code 3" in dead.message
        again = job.submit(4)  # a new worker: it dies too, and says so
        assert job.wait(again, 60) and "exit code 4" in again.message
    finally:
        job.close()


def _settle(session: Session, seconds: float = 60.0) -> None:
    """Poll like the page until the finite-strain curve of the current design is shown."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        session.poll()
        latest = session.finite_job.latest
        if session.finite_version == session.state.version and latest is not None and latest.ended:
            return
        time.sleep(0.05)
    raise AssertionError("the finite-strain curve never arrived")


def test_a_session_shows_the_newest_design_and_keeps_the_old_curve_until_then():
    session = Session("paper", p_max=1.0)
    seen: list[str] = []
    session.listeners.append(seen.append)
    try:
        session.recompute()
        _settle(session)
        old = session.finite
        assert [c.tier for c in session.curves] == ["paper", "section", "section-nonlinear"]
        session.edit("tube.h", 0.01)
        session.edit("tube.h", 0.02)  # supersedes the finite-strain curve of h = 0.01
        assert session.finite is old and not session.finite_is_current  # kept until the new one arrives
        _settle(session)
        assert session.finite_is_current and session.finite_version == 2
        assert session.finite is not old
        assert "inputs" in seen and "fast" in seen and "finite" in seen
        session.edit("tube.catalogue_inner_diameter", 0.9)  # refused: nothing recomputed
        assert session.state.version == 2 and "tube.catalogue_inner_diameter" in session.state.errors
    finally:
        session.close()


def test_a_tip_as_built_gets_its_finite_strain_curve():
    session = Session("paper", p_max=0.5)
    try:
        session.edit("assembly.tube_coil", "sliding")
        _settle(session)
        assert session.finite is not None and session.finite_message == ""
        assert [c.tier for c in session.curves] == ["paper", "section", "section-nonlinear"]
    finally:
        session.close()


def test_pin_keeps_a_design_under_later_ones():
    session = Session("paper", p_max=0.5)
    try:
        session.recompute()
        _settle(session)
        session.pin()
        pinned = session.pinned
        session.edit("tip.bending_length", 7.0)
        assert session.pinned is pinned and len(pinned) == 3
        assert "version 0" in session.pinned_label
        rows = design_numbers(session.curves, 0.3)
        assert all(r.unit for r in rows)
        session.unpin()
        assert session.pinned == []
    finally:
        session.close()


def test_numbers_carry_tier_load_and_unit_and_agree_with_the_models():
    d = design.preset("paper")
    p = np.linspace(0, 1.5, 31)
    curves = [formula_curve(d, p), linear_section_curve(d, p)]
    rows = {(r.quantity, r.tier): r for r in design_numbers(curves, 0.5)}
    p90 = rows[("pressure for a 90° bend", "the paper's formula")]
    assert p90.load.startswith("cap load") and p90.unit == "MPa"
    assert p90.value == pytest.approx(float(analytic.pressure_for_bend_angle(d, math.pi / 2)), rel=1e-9)
    bend = rows[("bend angle at 0.5 MPa", "the section model")]
    assert bend.load == "lumen load" and bend.unit == "°"
    assert rows[("max silicone strain at 0.5 MPa", "the paper's formula")].text() == "not given by this tier"


def test_an_uploaded_measurement_is_read_by_the_cli_reader():
    data = PAPER_SINE.read_bytes()
    m = read_upload(data, "C:\\lab\\run 1.csv")
    assert m.name == "run_1.csv" and m.pressure_MPa.size > 100
    assert np.isfinite(m.bend_angle_rad).all()  # κ × arc_length_mm
    with pytest.raises(DataError, match=r"^run_1.csv: .*pressure_MPa") as exc:
        read_upload(b"time_s,curvature_per_mm\n0,1\n", "run 1.csv")
    assert "\n" not in str(exc.value) and "softcath-upload" not in str(exc.value)
    with pytest.raises(DataError, match="larger than the 5 MB"):
        read_upload(b"x" * (MAX_UPLOAD_BYTES + 1), "big.csv")


def test_exports_round_trip(tmp_path, cli):
    session = Session("paper", p_max=0.5)
    try:
        session.edit("tube.h", 0.015)
        path = tmp_path / "design.toml"
        path.write_text(design_toml(session.state.design))
        assert cli("design", "validate", path).status == 0
        assert design.load(path) == session.state.design
        text = curves_csv([("current", c) for c in session.fast])
        lines = text.splitlines()
        assert lines[0].split(",") == list(CSV_COLUMNS)
        assert len(lines) == 1 + 2 * 61
        png = view_png(session.state.design, session.fast, pressure=0.3)
        assert png.startswith(b"\x89PNG")
    finally:
        session.close()


@pytest.mark.slow
def test_the_3d_check_runs_in_a_child_process_and_a_cancel_ends_it():
    """The real 3-D FEM (~10 s on the paper design): its curvature within 2 % of the linear section
    model's; a second run cancelled mid-way ends its process at once."""
    session = Session("paper", p_max=0.5, pressure=0.1)
    try:
        session.recompute()
        session.start_fem()
        end = time.monotonic() + 300
        while session.fem.poll().state == "running" and time.monotonic() < end:
            time.sleep(0.2)
        view = session.fem.poll()
        assert view.state == "done", view
        assert view.numbers["curvature_per_mm"] == pytest.approx(session.linear_at(0.1), rel=0.02)
        session.start_fem()
        proc = session.fem._proc
        time.sleep(1.0)
        session.cancel_fem()
        assert session.fem.poll().state == "cancelled" and not proc.is_alive()
    finally:
        session.close()


def test_view_is_a_panel_object_for_a_notebook():
    """``softcath.studies.app.view`` builds the same page without a server (what a notebook shows)."""
    import panel as pn

    page = view("paper", p_max=0.5)
    try:
        assert isinstance(page, pn.layout.Panel)
        html = page.select(pn.pane.HTML)
        assert any("softcath app: paper" in str(getattr(h, "object", "")) for h in html)
    finally:
        getattr(page, "_softcath_poll").stop()  # noqa: B009 - set by build(), unknown to the type


def test_pressure_controls_redraw_or_say_why_not():
    session = Session("paper", p_max=1.0, pressure=0.5)
    seen: list[str] = []
    session.listeners.append(seen.append)
    try:
        session.compute_fast()
        session.set_pressures(pressure=0.2)
        assert session.pressure == 0.2 and seen[-1] == "pressure"
        session.set_pressures(p_max=0.0)
        assert session.p_max == 1.0 and "largest pressure = 0: must be > 0 MPa" in session.messages[-1]
        session.set_pressures(p_max=1e9)
        assert session.p_max == 1.0 and "largest pressure" in session.messages[-1]
        session.set_pressures(p_max=2.0)
        assert session.fast[0].pressure_MPa[-1] == 2.0
    finally:
        session.close()
