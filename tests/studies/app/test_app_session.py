"""One app session without a browser: background work (newest wins), curves, numbers, uploads, exports."""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from softcath import analytic, design
from softcath.design.errors import DataError
from softcath.studies.app.curves import finite_strain_curve, formula_curve, linear_section_curve
from softcath.studies.app.export import CSV_COLUMNS, curves_csv, design_toml, view_png
from softcath.studies.app.jobs import LatestJob
from softcath.studies.app.measured import MAX_UPLOAD_BYTES, read_upload
from softcath.studies.app.numbers import design_numbers
from softcath.studies.app.page import Session
from softcath.studies.app.server import view

PAPER_SINE = Path(__file__).resolve().parents[3] / "studies" / "data" / "paper_sine.csv"


def _wait(ticket, seconds: float = 60.0) -> None:
    assert ticket.wait(seconds), f"ticket {ticket.number} still {ticket.state}"


def test_a_newer_finite_strain_request_supersedes_the_running_one():
    """Real finite-strain curves: the first is stopped at its next pressure, only the second finishes."""
    job = LatestJob("test")
    p = np.linspace(0.0, 1.0, 9)
    started = threading.Event()

    def curve(ticket, d):
        def progress(done, total):
            started.set()
            ticket.progress(done, total)

        return finite_strain_curve(d, p, on_pressure=progress)

    try:
        first = job.submit(curve, design.preset("paper"))
        assert started.wait(60)
        queued = job.submit(curve, design.preset("paper"))  # supersedes the first, then is superseded
        last = job.submit(curve, design.preset("paper").with_tube_shape(a=0.2, a_int=0.1, b_int=0.07, h=0.0))
        _wait(first), _wait(queued), _wait(last)
        assert (first.state, queued.state, last.state) == ("cancelled", "cancelled", "done")
        assert first.done < first.total  # stopped before its last pressure
        assert queued.done == 0  # never started
        assert job.latest is last and last.result.pressure_MPa.size == p.size
    finally:
        job.close()


def test_a_waiting_request_is_superseded_at_once():
    """The finite-strain request's start delay ends as soon as a newer request arrives."""
    job = LatestJob("test")
    try:
        waiting = job.submit(lambda ticket: ticket.sleep(30.0))
        time.sleep(0.1)
        t0 = time.monotonic()
        newer = job.submit(lambda ticket: "newer")
        _wait(newer, 5.0)
        assert waiting.state == "cancelled" and time.monotonic() - t0 < 5.0
    finally:
        job.close()


def test_a_crash_in_one_computation_leaves_the_job_working():
    job = LatestJob("test")
    try:
        bad = job.submit(lambda ticket: 1 / 0)
        _wait(bad)
        assert bad.state == "failed" and bad.message.startswith("unexpected ZeroDivisionError")
        good = job.submit(lambda ticket: "fine")
        _wait(good)
        assert (good.state, good.result) == ("done", "fine")
    finally:
        job.close()


def _settle(session: Session, seconds: float = 60.0) -> None:
    """Poll like the page until the finite-strain curve of the current design is shown."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        session.poll()
        if session.finite_version == session.state.version and session.finite_job.latest.state not in (
            "queued",
            "running",
        ):
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


def test_a_design_the_finite_strain_model_refuses_is_a_message_not_a_crash():
    session = Session("paper", p_max=0.5)
    try:
        session.edit("assembly.tube_coil", "sliding")
        _settle(session)
        assert session.finite is None
        assert "bonded tip only" in session.finite_message
        assert [c.tier for c in session.curves] == ["paper", "section"]  # the linear tiers take it
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
        assert any("softcath app: paper" in str(h.object) for h in html)
    finally:
        page._softcath_poll.stop()
