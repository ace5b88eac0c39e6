"""Three-mesh convergence study of the 3-D bend in the element layers: :func:`convergence_study`.

The same design and pressures on meshes with L/2, L and 2L layers along the
bending length (L the default of
:func:`~softcath.fem.nonlinear.convergence.default_layers` unless given): per
pressure the observed order of convergence of the mid-span curvature, its
Richardson extrapolation to infinitely many layers, and each mesh's relative
distance from it. :func:`write_study` writes ``convergence.csv``,
``convergence.json`` and ``convergence.png``; ``softcath fem DESIGN --nonlinear
--convergence`` is its command line.
"""

from __future__ import annotations

import csv
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath.core.plotting import pyplot
from softcath.fem.nonlinear.bend import bend_curve
from softcath.fem.nonlinear.convergence import (
    ASSUMED_ORDER,
    MIN_ESTIMATE_LAYERS,
    default_layers,
    extrapolate,
    observed_order,
)
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.reference import ErrorEstimate, estimate_error

__all__ = [
    "ConvergenceStudy",
    "convergence_study",
    "write_study",
    "write_study_csv",
    "plot_study",
    "STUDY_COLUMNS",
]

#: Columns of ``convergence.csv`` (one row per mesh and pressure).
STUDY_COLUMNS = (
    "pressure_MPa",
    "layers",
    "ndofs",
    "seconds",
    "curvature_mid_per_mm",
    "bend_angle_deg",
    "observed_order",
    "extrapolated_curvature_mid_per_mm",
    "relative_error_vs_extrapolated",
)

#: Observed orders outside this range are not trusted for the error estimate (the assumed one is used).
TRUSTED_ORDER = (0.5, 6.0)


@dataclass(frozen=True)
class ConvergenceStudy:
    """The 3-D bend on three meshes differing in element layers (arrays: mesh × pressure).

    Attributes
    ----------
    pressure
        Pressures [MPa].
    layers, ndofs, seconds
        Per mesh: element layers, DOFs and wall time of the solve [s].
    curvature_mid
        Mid-span curvature [1/mm].
    bend_angle
        Tip-end rotation [rad].
    order
        Observed order of convergence of the mid-span curvature per pressure (NaN if not monotone).
    extrapolated
        Richardson extrapolation of the mid-span curvature per pressure (observed order; NaN when
        the order is not defined).
    curves
        The three ``NonlinearFemCurve`` records; not serialised.
    """

    pressure: np.ndarray
    layers: tuple[int, int, int]
    ndofs: tuple[int, int, int]
    seconds: tuple[float, float, float]
    curvature_mid: np.ndarray
    bend_angle: np.ndarray
    order: np.ndarray
    extrapolated: np.ndarray
    curves: tuple = field(repr=False, compare=False, default=())

    @property
    def relative_error(self) -> np.ndarray:
        """|f − f_extrapolated| / |f_extrapolated| per mesh and pressure."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(self.curvature_mid - self.extrapolated) / np.abs(self.extrapolated)

    #: Axis labels of :func:`plot_study` (shared with the linear check's study, softcath.fem.mesh_study).
    value_label = "mid-span curvature [1/mm]"
    spacing_label = "1 / layers"

    @property
    def mesh_labels(self) -> tuple[str, ...]:
        """Legend label of each mesh."""
        return tuple(f"{n} layers" for n in self.layers)

    @property
    def values(self) -> np.ndarray:
        """The plotted quantity per mesh and pressure: the mid-span curvature [1/mm]."""
        return self.curvature_mid

    @property
    def spacing(self) -> np.ndarray:
        """Each mesh's 1/layers (the picture's abscissa)."""
        return 1.0 / np.asarray(self.layers, float)

    def error_estimate(self) -> ErrorEstimate:
        """The middle mesh's error estimate from the coarse one, with the top pressure's observed order.

        The observed order is used when it lies in :data:`TRUSTED_ORDER`; otherwise the
        assumed :data:`~softcath.fem.nonlinear.convergence.ASSUMED_ORDER`.
        """
        q = float(self.order[-1])
        if np.isfinite(q) and TRUSTED_ORDER[0] <= q <= TRUSTED_ORDER[1]:
            return estimate_error(self.curves[1], self.curves[0], order=q, order_source="observed")
        return estimate_error(self.curves[1], self.curves[0], order=ASSUMED_ORDER, order_source="assumed")

    def rows(self) -> list[dict]:
        """``convergence.csv`` rows (:data:`STUDY_COLUMNS`)."""
        rel = self.relative_error
        return [
            {
                "pressure_MPa": float(p),
                "layers": self.layers[m],
                "ndofs": self.ndofs[m],
                "seconds": self.seconds[m],
                "curvature_mid_per_mm": float(self.curvature_mid[m, j]),
                "bend_angle_deg": float(np.degrees(self.bend_angle[m, j])),
                "observed_order": float(self.order[j]),
                "extrapolated_curvature_mid_per_mm": float(self.extrapolated[j]),
                "relative_error_vs_extrapolated": float(rel[m, j]),
            }
            for j, p in enumerate(self.pressure)
            for m in range(3)
        ]

    def to_json(self) -> dict:
        """A JSON-ready dict (NaN as null)."""

        def clean(a):
            return [[_none(x) for x in row] for row in np.atleast_2d(a)]

        return {
            "quantity": "curvature_mid_per_mm",
            "pressure_MPa": [float(x) for x in self.pressure],
            "layers": list(self.layers),
            "ndofs": list(self.ndofs),
            "seconds": list(self.seconds),
            "curvature_mid_per_mm": clean(self.curvature_mid),
            "bend_angle_deg": clean(np.degrees(self.bend_angle)),
            "observed_order": clean(self.order)[0],
            "extrapolated_curvature_mid_per_mm": clean(self.extrapolated)[0],
            "relative_error_vs_extrapolated": clean(self.relative_error),
            "method": "three meshes L/2, L, 2L layers along the bending length; observed order q from "
            "(f1 - f2)/(f2 - f3) = (h1^q - h2^q)/(h2^q - h3^q), h = 1/layers; Richardson extrapolation "
            "from the two finest with q",
        }


def _none(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None


def study_layers(layers: int) -> tuple[int, int, int]:
    """The study's meshes for a middle mesh of ``layers``: (L/2, L, 2L)."""
    if not (isinstance(layers, (int, np.integer)) and layers >= MIN_ESTIMATE_LAYERS):
        raise SettingError(
            "layers", layers, f"must be an integer >= {MIN_ESTIMATE_LAYERS} for a three-mesh study"
        )
    return (int(layers) // 2, int(layers), 2 * int(layers))


def convergence_study(design, pressures, *, layers: int | None = None, **options) -> ConvergenceStudy:
    """Solve ``design`` at ``pressures`` on L/2, L and 2L layers and fit the convergence.

    Parameters
    ----------
    design, pressures
        As :func:`~softcath.fem.nonlinear.bend.bend_curve`.
    layers
        The middle mesh's layers L (default: ``bend_curve``'s default for the top pressure).
    **options
        Further keyword options of ``bend_curve`` (not ``mesh``).
    """

    if "mesh" in options:
        raise SettingError("mesh", "given", "a convergence study meshes its own layers")
    if layers is None:
        p = np.atleast_1d(np.asarray(pressures, float))
        layers = default_layers(design, float(p[-1]), load=options.get("load", "lumen")).layers
    curves, seconds = [], []
    for n in study_layers(layers):
        t0 = time.perf_counter()
        curves.append(bend_curve(design, pressures, layers=n, **options))
        seconds.append(time.perf_counter() - t0)
    lo, mid, hi = curves  # the three meshes of study_layers
    k = np.array([c.curvature_mid for c in curves])
    counts = tuple(c.layers for c in curves)
    order = np.array([observed_order(k[:, j], counts) for j in range(k.shape[1])])
    return ConvergenceStudy(
        pressure=np.asarray(curves[0].pressure, float),
        layers=counts,
        ndofs=(int(lo.ndofs), int(mid.ndofs), int(hi.ndofs)),
        seconds=(float(seconds[0]), float(seconds[1]), float(seconds[2])),
        curvature_mid=k,
        bend_angle=np.array([c.bend_angle for c in curves]),
        order=order,
        extrapolated=np.array([extrapolate(k[:, j], counts, order[j]) for j in range(k.shape[1])]),
        curves=tuple(curves),
    )


def write_study(study: ConvergenceStudy, out: Path) -> list[str]:
    """Write ``convergence.csv``, ``convergence.json`` and ``convergence.png`` into ``out``.

    Returns the names of the files written.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    write_study_csv(study, out / "convergence.csv")
    (out / "convergence.json").write_text(json.dumps(study.to_json(), indent=2), encoding="utf-8")
    plot_study(study, out / "convergence.png")
    return ["convergence.csv", "convergence.json", "convergence.png"]


def write_study_csv(study, path: Path) -> None:
    """``convergence.csv`` of a three-mesh study: its ``rows()``, floats to 9 digits."""
    rows = study.rows()
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v) for k, v in row.items()})


def plot_study(study, path: Path) -> None:
    """Left: curvature vs pressure per mesh and extrapolated (one pressure: vs the mesh spacing);
    right: error vs mesh spacing (log-log).

    ``study`` is a :class:`ConvergenceStudy` or the linear check's
    :class:`~softcath.fem.mesh_study.MeshStudy`: per mesh ``mesh_labels``, ``values`` (mesh ×
    pressure), ``spacing`` (1/layers or h) and their axis labels.
    """
    plt = pyplot()

    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.6))
    if study.pressure.size == 1:  # one pressure: the value against the mesh spacing
        a.plot(study.spacing, study.values[:, 0], "o-", label=f"p = {study.pressure[0]:g} MPa")
        a.axhline(study.extrapolated[0], color="k", ls="--", label="extrapolated")
        a.set_xlabel(study.spacing_label)
    else:
        for m, label in enumerate(study.mesh_labels):
            a.plot(study.pressure, study.values[m], "o-", ms=3, label=label)
        a.plot(study.pressure, study.extrapolated, "k--", label="extrapolated")
        a.set_xlabel("pressure [MPa]")
    a.set_ylabel(study.value_label)
    a.legend(fontsize=8)
    a.grid(alpha=0.3)
    rel = study.relative_error[:, -1]
    h = np.asarray(study.spacing, float)
    ok = np.isfinite(rel) & (rel > 0)
    if ok.any():
        b.loglog(h[ok], rel[ok], "o-", label=f"p = {study.pressure[-1]:g} MPa")
        q = study.order[-1]
        if np.isfinite(q):
            b.loglog(h, rel[ok][-1] * (h / h[ok][-1]) ** q, ":", label=f"slope {q:.2g} (observed)")
        b.legend(fontsize=8)
    b.set_xlabel(study.spacing_label)
    b.set_ylabel("relative error vs extrapolated")
    b.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
