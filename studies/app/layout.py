"""The page of one session: inputs on the left; figures, numbers, compare, export and the 3-D check.

:func:`build` makes the Panel layout of a :class:`~softcath.studies.app.page.Session`
and wires every widget to it. The same object is what ``softcath app`` serves
and what :func:`softcath.studies.app.view` shows in a notebook.
"""

from __future__ import annotations

import html
import io
import math

from softcath.studies.app.curves import LOAD_NOTE
from softcath.studies.app.export import curves_csv, design_toml, view_png
from softcath.studies.app.inputs import Inputs
from softcath.studies.app.numbers import design_numbers, validity_warnings
from softcath.studies.app.page import POLL_MS, Session
from softcath.studies.app.plots import TIER_ORDER, Figures
from softcath.studies.tiers import TIERS

__all__ = ["build"]


def _numbers_html(session: Session) -> str:
    rows = design_numbers(session.curves, session.pressure)
    pinned = {(r.quantity, r.tier): r for r in design_numbers(session.pinned, session.pressure)}
    head = "<th>quantity</th><th>tier</th><th>load</th><th>value</th><th>unit</th>"
    head += "<th>pinned A</th>" if session.pinned else ""
    body = ""
    for r in rows:
        cells = [r.quantity, r.tier, r.load, r.text(), r.unit]
        if session.pinned:
            a = pinned.get((r.quantity, r.tier))
            cells.append(a.text() if a else "")
        body += "<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in cells) + "</tr>"
    warnings = validity_warnings(session.curves, session.pressure)
    warn = "".join(f"<li>{html.escape(w)}</li>" for w in warnings)
    return (
        "<table class='numbers' style='font-size:12px;border-collapse:collapse' border='1' cellpadding='3'>"
        f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        + (
            f"<p><b>Validity warnings</b></p><ul class='warnings' style='font-size:12px'>{warn}</ul>"
            if warn
            else ""
        )
    )


def _finite_status(session: Session) -> tuple[str, int, int, bool]:
    """(text, done, total, running) of the finite-strain computation."""
    ticket = session.finite_job.latest
    label = TIERS["section-nonlinear"].label
    if ticket is not None and ticket.state in ("queued", "running"):
        kept = " (the previous design's curve is shown until then)" if session.finite is not None else ""
        return (
            f"{label}: computing, {ticket.done} of {ticket.total or '?'} pressures{kept}",
            ticket.done,
            max(ticket.total, 1),
            True,
        )
    if session.finite_message:
        return f"{label}: {session.finite_message}", 0, 1, False
    if session.finite is not None:
        return f"{label}: up to date (design version {session.finite_version})", 1, 1, False
    return f"{label}: not computed", 0, 1, False


def _fem_html(session: Session) -> str:
    view = session.fem.poll()
    if view.state == "running":
        return f"3-D linear FEM: running ({html.escape(view.stage)})"
    if view.state == "failed":
        return f"3-D linear FEM failed: {html.escape(view.message)}"
    if view.state == "cancelled":
        return "3-D linear FEM: cancelled"
    if view.state == "done":
        n = view.numbers
        p = n["pressure_MPa"]
        lin = session.linear_at(p)
        ratio = n["curvature_per_mm"] / lin if lin and math.isfinite(lin) else math.nan
        return (
            f"3-D linear FEM, lumen load, at {p:g} MPa: κ = {n['curvature_per_mm']:.4g} 1/mm, "
            f"θ = {math.degrees(n['bend_angle_rad']):.3g}°, ε = {n['elongation']:.3g}, "
            f"max silicone strain {n['max_strain']:.3g} ({n['dofs']} DOFs); "
            f"linear section model κ = {lin:.4g} 1/mm (3-D / section = {ratio:.3g})"
        )
    return "3-D linear FEM: not run (tens of seconds to minutes)"


def build(session: Session):
    """The Panel layout of ``session``, wired (periodic poll included)."""
    import panel as pn  # heavy (Bokeh, Tornado): imported only when an app is built

    figs = Figures()
    inputs = Inputs(session.state, session.edit)
    p_max = pn.widgets.FloatInput(
        label="largest pressure of the curves [MPa]",
        value=session.p_max,
        width=230,
        css_classes=["app-p-max"],
    )
    pressure = pn.widgets.FloatInput(
        label="chosen pressure: tip view and numbers [MPa]",
        value=session.pressure,
        width=230,
        css_classes=["app-pressure"],
    )
    p_max.param.watch(lambda e: session.set_pressures(p_max=e.new), "value")
    pressure.param.watch(lambda e: session.set_pressures(pressure=e.new), "value")

    marker = pn.pane.HTML("", css_classes=["app-version"], styles={"font-size": "11px", "color": "#666"})
    numbers = pn.pane.HTML("", css_classes=["app-numbers"])
    message = pn.pane.HTML("", css_classes=["app-message"], styles={"color": "#8a4b00"})
    finite_text = pn.pane.HTML("", css_classes=["app-finite"], styles={"font-size": "12px"})
    progress = pn.indicators.Progress(
        value=0, max=1, width=300, bar_color="success", css_classes=["app-progress"]
    )
    pin_text = pn.pane.HTML("", css_classes=["app-pinned"], styles={"font-size": "12px"})
    upload = pn.widgets.FileInput(accept=".csv", css_classes=["app-upload"])
    upload_clear = pn.widgets.Button(label="Remove the measurement", css_classes=["app-upload-clear"])
    pin = pn.widgets.Button(label="Pin this design as A", color="primary", css_classes=["app-pin"])
    unpin = pn.widgets.Button(label="Unpin A", css_classes=["app-unpin"])
    fem_run = pn.widgets.Button(label="Run the 3-D FEM check", color="warning", css_classes=["app-fem-run"])
    fem_cancel = pn.widgets.Button(label="Cancel the 3-D check", css_classes=["app-fem-cancel"])
    fem_text = pn.pane.HTML("", css_classes=["app-fem"], styles={"font-size": "12px"})
    fem_busy = pn.indicators.Progress(value=None, active=False, width=200, visible=False)

    def _toml():
        return io.StringIO(design_toml(session.state.design))

    def _csv():
        curves = [("current", c) for c in session.curves] + [("pinned A", c) for c in session.pinned]
        return io.StringIO(curves_csv(curves))

    def _png():
        png = view_png(
            session.state.design,
            session.curves,
            pressure=session.pressure,
            pinned=session.pinned,
            measured=session.measured,
        )
        return io.BytesIO(png)

    downloads = [
        pn.widgets.FileDownload(
            callback=_toml, filename="design.toml", label="Design (TOML)", css_classes=["app-export-toml"]
        ),
        pn.widgets.FileDownload(
            callback=_csv, filename="curves.csv", label="Curves (CSV)", css_classes=["app-export-csv"]
        ),
        pn.widgets.FileDownload(
            callback=_png, filename="softcath-app.png", label="View (PNG)", css_classes=["app-export-png"]
        ),
    ]

    upload.param.watch(lambda e: session.upload(e.new, upload.filename), "value")
    upload_clear.on_click(lambda e: session.clear_measured())
    pin.on_click(lambda e: session.pin())
    unpin.on_click(lambda e: session.unpin())
    fem_run.on_click(lambda e: session.start_fem())
    fem_cancel.on_click(lambda e: session.cancel_fem())

    def redraw(what: str) -> None:
        if what == "inputs":
            inputs.show(session.state)
        if what == "message":
            message.object = "<br>".join(html.escape(m) for m in session.messages[-3:])
        if what == "fast":
            figs.show_section(session.state.design)
            figs.show_curves(session.fast, tiers=("paper", "section"))
            figs.show_tip(session.fast, session.pressure, tiers=("paper", "section"))
            marker.object = (
                f"design version {session.state.version}; linear curve of version {session.state.version}"
            )
        if what == "finite":
            figs.show_curves(session.curves, tiers=("section-nonlinear",))
            figs.show_tip(session.curves, session.pressure, tiers=("section-nonlinear",))
        if what == "pressure":
            figs.show_tip(session.curves, session.pressure, tiers=TIER_ORDER)
            figs.show_tip(session.pinned, session.pressure, pinned=True, tiers=TIER_ORDER)
        if what == "pinned":
            figs.show_curves(session.pinned, pinned=True, tiers=TIER_ORDER)
            figs.show_tip(session.pinned, session.pressure, pinned=True, tiers=TIER_ORDER)
            pin_text.object = html.escape(session.pinned_label) if session.pinned else "nothing pinned"
        if what == "measured":
            figs.show_measured(session.measured)
        if what == "fem-check":  # the 3-D FEM check's panel
            fem_text.object = _fem_html(session)
            running = session.fem.poll().state == "running"
            fem_busy.visible = fem_busy.active = running
        if what in ("fast", "finite", "pressure", "pinned"):
            numbers.object = _numbers_html(session)
        if what in ("fast", "finite", "finite-progress"):
            text, done, total, _ = _finite_status(session)
            finite_text.object = html.escape(text)
            progress.max, progress.value = total, done

    session.listeners.append(redraw)
    session.recompute()
    for what in ("pinned", "fem-check", "measured"):
        redraw(what)

    legend_note = pn.pane.HTML(
        "<small>Every curve: tier and load in its legend. The paper's formula is the "
        f"{html.escape(LOAD_NOTE['paper'])}; the section models take the lumen load (wall and cap). "
        "Units: mm, MPa, 1/mm; angles in degrees.</small>"
    )
    sidebar = pn.Column(
        pn.pane.HTML(f"<h3>softcath app: {html.escape(session.state.design.name)}</h3>"),
        p_max,
        pressure,
        *inputs.cards,
        width=300,
        scroll=True,
        height=900,
    )
    main = pn.Column(
        message,
        pn.Row(figs.section, figs.tip),
        pn.Row(figs.kappa, figs.theta),
        legend_note,
        pn.Row(progress, finite_text),
        marker,
        pn.pane.HTML("<h4>Numbers</h4>"),
        numbers,
        pn.pane.HTML("<h4>Compare</h4>"),
        pn.Row(pin, unpin, pin_text),
        pn.Row(
            pn.pane.HTML("measured CSV (time_s, pressure_MPa, curvature_per_mm, …; ≤ 5 MB):"),
            upload,
            upload_clear,
        ),
        pn.pane.HTML("<h4>Export</h4>"),
        pn.Row(*downloads),
        pn.pane.HTML("<h4>3-D FEM check (the current design at the chosen pressure, lumen load)</h4>"),
        pn.Row(fem_run, fem_cancel, fem_busy),
        fem_text,
    )
    page = pn.Row(sidebar, main)
    callback = pn.state.add_periodic_callback(session.poll, period=POLL_MS)
    page._softcath_poll = callback  # type: ignore[attr-defined]  # kept alive with the page
    return page
