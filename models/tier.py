"""A model tier: its names, its capabilities and its one way of answering.

Every tier is a :class:`Tier`: the naming fields (``name``, ``label``, ``short_label``,
``description``, ``column_stem``), the capability data the consumers read instead of
comparing names (the loads and options it takes, the bend it is valid to, whether it models
an as-built assembly, the notes a prediction band carries), and two methods:
:meth:`Tier.response` for one design and :meth:`Tier.responses` for many (vectorised or
batched where the tier can be). A tier implements :meth:`Tier._solve` only; the checks of
loads and options are here, once.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from softcath.core.response import OBSERVABLES, ResponseBatch, TipResponse, tip_curvature
from softcath.design.assembly import Assembly
from softcath.design.errors import DesignError
from softcath.models.validity import response_warnings

__all__ = ["LOADS", "OptionBound", "REGISTERED", "SLOW_SECONDS", "Tier"]

#: The loads a tier can be asked about: the end-cap force alone, or the lumen pressure on wall and cap.
LOADS = ("cap", "lumen")
#: The registered tiers, name -> tier (filled by :func:`softcath.models.register`).
REGISTERED: dict[str, Tier] = {}
#: Seconds a design above which a tier is slow: minutes a design, not a search's thousands of runs.
SLOW_SECONDS = 10.0


@dataclass(frozen=True)
class OptionBound:
    """The interval a numeric tier option must lie in (closed unless an end is marked open)."""

    low: float = -math.inf
    high: float = math.inf
    open_low: bool = False
    open_high: bool = False

    def __contains__(self, value: object) -> bool:
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            return False
        v = float(value)
        above = v > self.low if self.open_low else v >= self.low
        below = v < self.high if self.open_high else v <= self.high
        return above and below

    def __str__(self) -> str:
        return f"{'(' if self.open_low else '['}{self.low:g}, {self.high:g}{')' if self.open_high else ']'}"


@dataclass(frozen=True)
class Tier:
    """One model tier (the naming fields first, then its capabilities).

    Attributes
    ----------
    name
        The tier's one name (sweep evaluators, ``--model``, JSON).
    label
        Noun phrase for prose, e.g. ``"the paper's formula"``.
    short_label
        Legend label for plots, e.g. ``"paper's formula (eq. 7)"``.
    description
        One line: what the tier computes and what it costs.
    column_stem
        The word that marks the tier's columns in sweep results
        (``curvature_analytic_per_mm``, ``nonlinear_curvature_per_mm``), kept from
        earlier versions so stored sweeps still read and resume.
    loads
        The loads the tier answers.
    default_load
        The load it is about unless told (the paper's formula is a cap-load model).
    options
        Option name -> its default: the only options :meth:`response` accepts.
    option_choices
        Option name -> the values it may take, for an option with a closed set of values
        (checked with the others by :meth:`check_options`).
    option_bounds
        Option name -> the :class:`OptionBound` a numeric option must lie in (checked by
        :meth:`check_options` before any design is solved).
    valid_to_deg
        Bend angle [deg] up to which the tier holds (:mod:`softcath.models.validity`):
        finite for a small-rotation (linear) tier, infinite for a finite-strain one.
    as_built
        Whether it models an as-built ``[assembly]`` itself (sliding or tied interfaces, a
        coat or no filler, a free base); a tier that does not is one bonded body.
    load_notes
        Load -> what a result under that load means for this tier (e.g. the paper's formula
        under the lumen load is its cap gain times (1 - 2ν)).
    range_notes
        Design-parameter suffix -> how the tier treats a sampled range of it (e.g. the 3-D
        FEM's cap on Poisson ratios).
    dof_seconds
        Estimated seconds of one run per section degree of freedom; 0 for a closed form.
    seconds_per_design
        Rough wall time of one design at a few pressures and both loads [s]; a tier above
        :data:`SLOW_SECONDS` is slow (the searches and robust samples do not offer it, and a
        prediction band counts its own sample size for it).
    batched
        Whether :meth:`responses` shares work between designs (then a sweep gives it many
        designs a task) rather than solving them one by one.
    closed_form
        Whether the tier is a closed-form formula (the paper's eq. 7): no mesh and no solve, it
        always runs beside the others, and it is defined for its default load (its other
        loads are variants of it).
    section_mesh
        Whether it solves on the 2-D section mesh (the section models): a sweep's
        ``[sweep.section]`` table is its, and its cost scales with the section's degrees of
        freedom (:attr:`dof_seconds`).
    finite_strain_tier
        The name of its finite-strain counterpart (the same model without the small-rotation
        assumption), or ``None``: what a large bend on this tier is re-checked with.
    """

    name: str
    label: str
    short_label: str
    description: str
    column_stem: str
    loads: tuple[str, ...] = LOADS
    default_load: str = "lumen"
    options: Mapping[str, Any] = field(default_factory=dict, compare=False)
    option_choices: Mapping[str, tuple] = field(default_factory=dict, compare=False)
    option_bounds: Mapping[str, OptionBound] = field(default_factory=dict, compare=False)
    valid_to_deg: float = math.inf
    as_built: bool = False
    load_notes: Mapping[str, str] = field(default_factory=dict, compare=False)
    range_notes: Mapping[str, str] = field(default_factory=dict, compare=False)
    dof_seconds: float = 0.0
    seconds_per_design: float = math.inf
    batched: bool = False
    closed_form: bool = False
    section_mesh: bool = False
    finite_strain_tier: str | None = None

    @property
    def slow(self) -> bool:
        """Whether one design takes longer than :data:`SLOW_SECONDS` (the 3-D FEM tiers)."""
        return self.seconds_per_design > SLOW_SECONDS

    @property
    def linear(self) -> bool:
        """Whether the tier is a small-rotation one (valid to a finite bend only)."""
        return math.isfinite(self.valid_to_deg)

    # -- the checks every tier shares ---------------------------------------------------------

    def check_load(self, load: str, *, parameter: str = "load") -> str:
        """``load`` if the tier answers it, else a :class:`DesignError` naming what it accepts."""
        if load not in self.loads:
            raise DesignError(parameter, load, f"{self.name} answers the loads {', '.join(self.loads)}")
        return load

    def check_options(self, options: Mapping[str, Any] | None, *, parameter: str = "options") -> dict:
        """The options with ``None`` values dropped; an option the tier does not take, or a value
        outside its :attr:`option_choices` or :attr:`option_bounds`, is refused."""
        given = {k: v for k, v in (options or {}).items() if v is not None}
        unknown = sorted(set(given) - set(self.options))
        if unknown:
            accepted = ", ".join(self.options) or "none"
            raise DesignError(
                f"{parameter}.{unknown[0]}", given[unknown[0]], f"{self.name} accepts the options {accepted}"
            )
        for k, v in given.items():
            choices = self.option_choices.get(k)
            if choices is not None and v not in choices:
                raise DesignError(f"{parameter}.{k}", v, f"{self.name} takes {', '.join(map(str, choices))}")
            bound = self.option_bounds.get(k)
            if bound is not None and v not in bound:
                raise DesignError(f"{parameter}.{k}", v, f"must be in {bound} ({self.name})")
        return given

    def own_options(self, options: Mapping[str, Any] | None) -> dict:
        """The subset of ``options`` this tier takes (of a shared table, e.g. ``[sweep.section]``)."""
        return {k: v for k, v in (options or {}).items() if k in self.options and v is not None}

    def parameters(self, design, options: Mapping[str, Any]) -> dict:
        """The parameters a response used: the options over their defaults, the design's name and length."""
        return {
            "design": getattr(design, "name", None),
            "bending_length_mm": float(design.tip.bending_length),
            **dict(self.options),
            **dict(options),
        }

    def warnings(self, pressures, bend_angle_rad, max_strain=None, elongation=None) -> tuple[str, ...]:
        """The validity warnings of one response (:func:`~softcath.models.validity.response_warnings`)."""
        return response_warnings(
            self, pressures, bend_angle_rad, max_strain=max_strain, elongation=elongation
        )

    def available(self) -> bool:
        """Whether this build can run the tier (the 3-D FEM needs its optional dependencies)."""
        return True

    @staticmethod
    def _assembly(assembly):
        return assembly if isinstance(assembly, Assembly) else Assembly.from_dict(assembly or {})

    def check_assembly(self, assembly, *, parameter: str = "assembly") -> None:
        """Refuse an as-built ``assembly`` this tier would answer with its bonded model.

        Parameters
        ----------
        assembly
            The design's :class:`~softcath.design.assembly.Assembly` (or its ``[assembly]`` table).
        parameter
            How the caller names the assembly (``assembly``, ``--assembly``).

        Raises
        ------
        DesignError
            Naming ``parameter`` with the options that differ from the bonded tip and the tiers
            that model them.
        """
        a = self._assembly(assembly)
        if a.is_default or self.as_built:
            return
        base = Assembly()
        changed = {k: v for k, v in a.to_dict().items() if getattr(base, k) != v}
        modelled = [t for t in REGISTERED.values() if t.as_built]
        labels = [t.label for t in modelled]
        names = " and ".join(labels) if len(labels) < 3 else f"{', '.join(labels[:-1])} and {labels[-1]}"
        raise DesignError(
            parameter,
            changed,
            f"is modelled by {names} only "
            f"({self.label} is one bonded body and would answer another tip); use --model {modelled[0].name}",
        )

    # -- answering ------------------------------------------------------------------------------

    def response(
        self, design, pressures: Sequence[float] | np.ndarray, *, load: str | None = None, options=None
    ) -> TipResponse:
        """The response of one ``design`` at ``pressures`` [MPa] under ``load`` (default: the default load).

        Raises
        ------
        DesignError
            An unsupported load or option; the tier's own errors propagate.
        """
        load = self.default_load if load is None else load
        batch = self.responses([design], pressures, loads=(load,), options=options)[load]
        return batch[0]

    def responses(
        self,
        designs: Sequence,
        pressures: Sequence[float] | np.ndarray,
        *,
        loads: Sequence[str] | None = None,
        options=None,
    ) -> dict[str, ResponseBatch]:
        """The responses of many ``designs``: ``{load: ResponseBatch}``.

        A design the tier cannot solve gets NaN rows and its exception in the batch's
        ``errors``: one design never stops the others.
        """
        loads = (self.default_load,) if loads is None else tuple(loads)
        for load in loads:
            self.check_load(load)
        opts = self.check_options(options)
        p = np.atleast_1d(np.asarray(pressures, dtype=float))
        return self._solve(list(designs), p, loads, opts)

    def _solve(self, designs: list, pressures: np.ndarray, loads: tuple[str, ...], options: dict):
        """The tier's computation: ``{load: ResponseBatch}`` (implemented by each tier)."""
        raise NotImplementedError(f"tier {self.name} has no computation")

    # -- helpers for implementations --------------------------------------------------------------

    def _batch(self, designs: list, pressures: np.ndarray, load: str, values: dict, **rest) -> ResponseBatch:
        """A :class:`ResponseBatch` from ``values`` (observable -> (n, n_p) array; missing ones NaN)."""
        shape = (len(designs), pressures.size)
        cols = {
            k: np.asarray(values[k], float) if k in values else np.full(shape, np.nan) for k in OBSERVABLES
        }
        tip = cols["tip_curvature_per_mm"]
        if np.isnan(tip).any():  # the tier's own where it gives one, else bend angle over deformed length
            lengths = np.array(
                [[d.tip.bending_length] if d is not None else [np.nan] for d in designs], float
            )
            arc = tip_curvature(cols["bend_angle_rad"], cols["elongation"], lengths)
            cols["tip_curvature_per_mm"] = np.where(np.isnan(tip), arc, tip)
        rest.setdefault("seconds", np.full(len(designs), np.nan))
        return ResponseBatch(
            tier=self.name, load=load, pressures=pressures, **cols, designs=tuple(designs), model=self, **rest
        )
