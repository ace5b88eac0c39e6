"""Prediction bands' result files: ``prediction.json``, ``samples.csv`` and the band figures.

:func:`prediction_run` gathers what ``softcath predict`` reports: the bands of the
chosen tier and the compared ones (:func:`softcath.studies.predict.predict`), optionally
the nominal design's finite-strain point and the finite-strain section model's curve
bands; :meth:`PredictionRun.write` writes the files the command writes, all or none:

- ``prediction.json``: the bands, measured position, sensitivity and ranges (plus
  ``finite_strain`` and ``nonlinear`` when asked for);
- ``samples.csv``: one row per variant and tier (parameters a tier does not use empty,
  empty gains for variants the design checks reject);
- ``prediction.png``: each tier's band and the measured line;
- ``curve_band.png``: the curve bands (with the curve bands only).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.design.errors import DesignError
from softcath.studies.outputs.tables import write_rows
from softcath.studies.predict import TierPrediction, predict
from softcath.studies.predict.curve_band import curve_bands
from softcath.studies.predict.finite_strain import finite_strain_point
from softcath.studies.predict.plot import band_picture, curve_band_picture

__all__ = ["PredictionRun", "prediction_run", "samples_table"]


@dataclass(frozen=True)
class PredictionRun:
    """A design's prediction bands and what ``softcath predict`` draws beside them.

    Attributes
    ----------
    doc
        ``prediction.json``'s document.
    tiers
        Each tier's band (:class:`~softcath.studies.predict.TierPrediction`).
    measured_gain
        The measured κ/p [1/(mm MPa)] drawn as a line, or None.
    measured
        The measured curve placed in the curve bands, or None.
    points
        Extra labelled gains drawn in the band picture (the finite-strain point).
    """

    doc: dict
    tiers: tuple[TierPrediction, ...]
    measured_gain: float | None = None
    measured: object = None
    points: dict[str, float] = field(default_factory=dict)

    def to_json(self) -> dict:
        """``prediction.json``'s document."""
        return self.doc

    def to_table(self) -> tuple[list[str], list[list[str]]]:
        """``samples.csv``: (header, rows); see :func:`samples_table`."""
        return samples_table(self.tiers)

    def write(self, folder: str | Path) -> tuple[str, ...]:
        """Write the prediction's files into ``folder``, all or none; return their names."""
        names = ["prediction.json", "samples.csv", "prediction.png"]
        design = self.doc["design"]
        with Outputs(prepare_out_dir(folder, param="folder")) as o:
            o.json("prediction.json", self.doc)
            if "nonlinear" in self.doc:
                curve_band_picture(
                    self.doc["nonlinear"],
                    o.path("curve_band.png"),
                    measured=self.measured,
                    title=f"{design}: finite-strain section model, curvature bands",
                )
                names.append("curve_band.png")
            write_rows(o.path("samples.csv"), *self.to_table())
            band_picture(
                self.tiers,
                o.path("prediction.png"),
                measured_gain=self.measured_gain,
                points=self.points,
                title=f"{design}: κ/p bands (box p5–p95, bar p50, ◆ nominal)",
            )
        return tuple(names)


def samples_table(tiers: Sequence[TierPrediction]) -> tuple[list[str], list[list[str]]]:
    """One row per variant and tier: tier, load, parameter values, κ/p and ε/p.

    Parameters a tier does not use are left empty, as are the gains of variants the
    design checks reject (NaN).
    """
    names = list(dict.fromkeys(r.path for t in tiers for r in t.ranges))
    header = ["tier", "load", *names, "curvature_per_mm_per_MPa", "elongation_per_MPa"]
    rows = []
    for t in tiers:
        for row, k, e in zip(t.values, t.gains, t.elongations, strict=True):
            cells = [row.get(n, "") for n in names]
            cells = [f"{c:.10g}" if isinstance(c, float) else c for c in cells]
            rows.append([t.model, t.load, *cells, *("" if v != v else f"{v:.10g}" for v in (k, e))])
    return header, rows


def prediction_run(
    design_ref,
    *,
    model: str = "section",
    compare: Sequence[str] = (),
    load: str | None = None,
    vary: Sequence[str] = (),
    ranges_file: str | Path | None = None,
    samples: int | None = None,
    fem_samples: int | None = None,
    seed: int = 0,
    measured_gain: float | None = None,
    finite_strain_pressures: Sequence[float] | None = None,
    curve_pressures: Sequence[float] | None = None,
    curve_samples: int = 64,
    measured=None,
    progress: bool = False,
    options=None,
) -> PredictionRun:
    """The prediction bands of a design, with the finite-strain point and curve bands when asked.

    The keywords up to ``measured_gain``, and ``options``, are :func:`softcath.studies.predict.predict`'s.

    Parameters
    ----------
    finite_strain_pressures
        Pressures [MPa] of the nominal design's finite-strain point
        (:func:`~softcath.studies.predict.finite_strain.finite_strain_point`), or None.
    curve_pressures
        Pressures [MPa] of the finite-strain section model's curve bands
        (:func:`~softcath.studies.predict.curve_band.curve_bands`), or None.
    curve_samples
        The curve bands' sample size (a refusal names it ``curve_samples``).
    measured
        A :class:`~softcath.design.measurement.Measurement` placed in the curve bands.
    """
    doc, tiers = predict(
        design_ref,
        model=model,
        compare=compare,
        load=load,
        vary=vary,
        ranges_file=ranges_file,
        samples=samples,
        fem_samples=fem_samples,
        seed=seed,
        measured_gain=measured_gain,
        progress=progress,
        options=options,
    )
    points = {}
    if finite_strain_pressures is not None:
        fs = finite_strain_point(
            design_ref,
            finite_strain_pressures,
            load=load or "lumen",
            measured_gain=measured_gain,
            progress=progress,
        )
        doc["finite_strain"] = fs
        points[f"finite-strain FEM, nominal\n{fs['load']} load, line fit"] = fs["gain_line_fit"]
    if curve_pressures is not None:
        try:
            doc["nonlinear"] = curve_bands(
                design_ref,
                curve_pressures,
                vary=vary,
                ranges_file=ranges_file,
                samples=curve_samples,
                seed=seed,
                load=load or "lumen",
                measured=measured,
                progress=progress,
            )
        except DesignError as exc:  # the bands' own sample size is not the tiers'
            if exc.parameter != "samples":
                raise
            raise DesignError("curve_samples", exc.value, exc.bound) from None
    return PredictionRun(
        doc=doc, tiers=tuple(tiers), measured_gain=measured_gain, measured=measured, points=points
    )
