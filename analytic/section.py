r"""The composite cross-section of the tip (paper eqs. 3–7).

Components (paper numbering): 1 outer coil, 2 silicone tube, 3 hollow
channel, plus the dip-coat filler when the design has one. Each carries an
axial modulus; the two coils are homogenised by :mod:`softcath.design.coil_mechanics`.

- Axial stiffness ΣEA = Σ E_i A_i (coils with their tension modulus, as the
  paper's E_eq from the spring constant).
- Neutral axis (eq. 5): ȳ = Σ E_i A_i ȳ_i / Σ E_i A_i.
- Bending stiffness (eq. 6–7): ΣEI = Σ E_i I_i(ȳ), **each I_i taken about the
  composite neutral axis ȳ** by the parallel-axis theorem. The paper's eq. 7
  writes ΣE_iI_i and leaves the axis implicit; taking each part about its own
  centroid would drop the E_iA_i(ȳ_i − ȳ)² terms, which here are most of the
  stiffness of the offset channel. For a coil, E_i I_i about its own centre is
  the helical-spring bending stiffness (Wahl), and its offset term uses its
  axial modulus: the coil resists the bending of the composite by stretching.
- Pressure acts on the lumen: A_p = π a_int b_int, centre y_p = y_t + h.

Vectorised: :func:`section_arrays` takes arrays (broadcast) of the design
numbers from :func:`design_inputs`, so many designs evaluate at once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.analytic import shapes
from softcath.design import TipDesign
from softcath.design.coil_mechanics import coil_stiffness_arrays

__all__ = [
    "CompositeSection",
    "composite_section",
    "design_inputs",
    "design_inputs_many",
    "section_arrays",
    "INPUT_KEYS",
]

INPUT_KEYS = (
    "coil_od",
    "coil_id",
    "coil_wire",
    "coil_pitch",
    "coil_E",
    "coil_nu",
    "channel_od",
    "channel_id",
    "channel_wire",
    "channel_pitch",
    "channel_E",
    "channel_nu",
    "tube_E",
    "tube_nu",
    "filler_E",
    "a",
    "a_int",
    "b_int",
    "h",
    "length",
)


def design_inputs(design: TipDesign) -> dict[str, float]:
    """The numbers of ``design`` that the analytic model uses (mm, MPa), keyed by :data:`INPUT_KEYS`."""
    c, ch, t = design.coil, design.channel, design.tube
    shape = design.tube_shape
    return {
        "coil_od": c.outer_diameter,
        "coil_id": c.inner_diameter,
        "coil_wire": c.wire_diameter,
        "coil_pitch": c.pitch,
        "coil_E": c.material.youngs_modulus,
        "coil_nu": c.material.poisson_ratio,
        "channel_od": ch.outer_diameter,
        "channel_id": ch.inner_diameter,
        "channel_wire": ch.wire_diameter,
        "channel_pitch": ch.pitch,
        "channel_E": ch.material.youngs_modulus,
        "channel_nu": ch.material.poisson_ratio,
        "tube_E": t.material.youngs_modulus,
        "tube_nu": t.material.poisson_ratio,
        "filler_E": 0.0 if design.filler is None else design.filler.youngs_modulus,
        **shape,
        "length": design.tip.bending_length,
    }


def design_inputs_many(designs) -> dict[str, np.ndarray]:
    """:func:`design_inputs` of many designs as arrays (one entry per design), for :func:`section_arrays`."""
    rows = [design_inputs(d) for d in designs]
    return {k: np.array([r[k] for r in rows], dtype=float) for k in INPUT_KEYS}


def section_arrays(inp: dict) -> dict[str, np.ndarray]:
    """Composite section quantities for arrays of inputs (numpy broadcasting).

    Returns a dict with ``EA`` [N], ``EI`` [N mm²] about the neutral axis,
    ``neutral_axis_y``, ``pressure_area`` [mm²], ``pressure_centre_y`` [mm],
    ``eccentricity`` = y_p − ȳ [mm], and per-component ``EA_*``, ``EI_*``, ``y_*``.
    """
    r_in = np.asarray(inp["coil_id"], float) / 2
    r_co = np.asarray(inp["coil_od"], float) / 2
    r_c = np.asarray(inp["channel_od"], float) / 2
    r_ci = np.asarray(inp["channel_id"], float) / 2
    b = r_in - r_c
    y_t = r_in - b
    y_c = -(r_in - r_c)
    a, a_int, b_int, h = (np.asarray(inp[k], float) for k in ("a", "a_int", "b_int", "h"))

    coil = coil_stiffness_arrays(
        outer_diameter=inp["coil_od"],
        inner_diameter=inp["coil_id"],
        wire_diameter=inp["coil_wire"],
        pitch=inp["coil_pitch"],
        youngs_modulus=inp["coil_E"],
        poisson_ratio=inp["coil_nu"],
    )
    chan = coil_stiffness_arrays(
        outer_diameter=inp["channel_od"],
        inner_diameter=inp["channel_id"],
        wire_diameter=inp["channel_wire"],
        pitch=inp["channel_pitch"],
        youngs_modulus=inp["channel_E"],
        poisson_ratio=inp["channel_nu"],
    )
    m_coil = shapes.annulus(r_co, r_in, 0.0)
    m_chan = shapes.annulus(r_c, r_ci, y_c)
    m_tube = shapes.hollow_ellipse(a, b, a_int, b_int, h, y_t)
    m_fill = shapes.disc(r_in) - shapes.ellipse(a, b, y_t) - shapes.disc(r_c, y_c)

    e_coil, e_chan = coil["axial_modulus_tension"], chan["axial_modulus_tension"]
    e_tube, e_fill = np.asarray(inp["tube_E"], float), np.asarray(inp["filler_E"], float)
    ea_parts = {
        "coil": e_coil * m_coil.area,
        "tube": e_tube * m_tube.area,
        "channel": e_chan * m_chan.area,
        "filler": e_fill * m_fill.area,
    }
    eq_parts = (e_coil * m_coil.first, e_tube * m_tube.first, e_chan * m_chan.first, e_fill * m_fill.first)
    ea = sum(ea_parts.values())
    ybar = sum(eq_parts) / ea
    ei_parts = {
        # own bending (Wahl) + offset stretching about the neutral axis
        "coil": coil["bending_stiffness"] + e_coil * m_coil.area * ybar**2,
        "tube": e_tube * m_tube.about(ybar),
        "channel": chan["bending_stiffness"] + e_chan * m_chan.area * (y_c - ybar) ** 2,
        "filler": e_fill * m_fill.about(ybar),
    }
    ei = sum(ei_parts.values())
    ap = np.pi * a_int * b_int
    yp = y_t + h
    out = {
        "EA": ea,
        "EI": ei,
        "neutral_axis_y": ybar,
        "pressure_area": ap,
        "pressure_centre_y": yp,
        "eccentricity": yp - ybar,
        "tube_centre_y": y_t,
        "b": b,
    }
    for k, v in ea_parts.items():
        out[f"EA_{k}"] = v
    for k, v in ei_parts.items():
        out[f"EI_{k}"] = v
    out["y_coil"] = np.zeros_like(ybar)
    out["y_tube"] = m_tube.centroid
    out["y_channel"] = y_c + 0 * ybar
    out["y_filler"] = m_fill.centroid
    return out


@dataclass(frozen=True, kw_only=True)
class CompositeSection:
    """Composite section of one design (mm, N, MPa).

    Attributes
    ----------
    EA
        Axial stiffness ΣE_iA_i [N].
    EI
        Bending stiffness ΣE_iI_i about the composite neutral axis [N mm²].
    neutral_axis_y
        ȳ (eq. 5) [mm].
    pressure_area
        A_p, the lumen area [mm²].
    pressure_centre_y
        y_p, the lumen centroid [mm].
    eccentricity
        e = y_p − ȳ [mm].
    parts
        Per component (coil, tube, channel, filler): ``EA``, ``EI`` (about ȳ) and ``y`` (centroid).
    """

    EA: float
    EI: float
    neutral_axis_y: float
    pressure_area: float
    pressure_centre_y: float
    eccentricity: float
    parts: dict[str, dict[str, float]]


def composite_section(design: TipDesign) -> CompositeSection:
    """The composite section of ``design`` (see module docstring)."""
    s = section_arrays(design_inputs(design))
    parts = {
        k: {"EA": float(s[f"EA_{k}"]), "EI": float(s[f"EI_{k}"]), "y": float(s[f"y_{k}"])}
        for k in ("coil", "tube", "channel", "filler")
    }
    return CompositeSection(
        EA=float(s["EA"]),
        EI=float(s["EI"]),
        neutral_axis_y=float(s["neutral_axis_y"]),
        pressure_area=float(s["pressure_area"]),
        pressure_centre_y=float(s["pressure_centre_y"]),
        eccentricity=float(s["eccentricity"]),
        parts=parts,
    )
