"""The sweep specification: a TOML file naming a base design, parameters, pressures, loads, evaluators.

Layout::

    [sweep]
    name = "quick"
    base = "paper"                 # a preset name or a design TOML path (relative to the spec)
    pressures_MPa = [0.0, 0.5, 1.0]
    loads = ["cap", "lumen"]
    evaluators = ["paper"]         # and/or "section" (2-D section model, ~13 ms/design),
                                   # "section-nonlinear" (finite-strain section model, ~1 s/design
                                   # and load: large bends), "fem", "fem-nonlinear" (finite-strain
                                   # FEM, slow); the names of softcath.studies.tiers ("analytic" and
                                   # "nonlinear" still read, with a deprecation warning)
    seed = 7                       # Latin hypercube seed
    chunk_size = 500               # designs per task (FEM tasks are always one design)

    [sweep.fem]
    mesh_size = 0.12               # mm, section element size passed to fem.check

    [sweep.section]                # options of the section model (all optional)
    mesh_size = 0.05               # mm, element size of the 2-D section mesh
    coil_bending = "annulus"       # or "wahl" (+ the coils' helical-spring bending stiffness)
    mesher = "template"            # or "gmsh" (a fresh mesh per design; template is within 0.2 %)

    [sweep.options.section]        # any tier's options (softcath.models.Tier.options), by tier
    poisson_cap = 0.49             # (the tier must be one of the sweep's evaluators)

    [sweep.feasibility]
    max_strain = 0.3               # silicone strain limit [-]

    [sample]                       # only needed for "lhs" parameters
    n = 64

    [parameters]                   # dotted paths into the base design's TOML tables
    "tube.h" = { grid = [-0.02, 0.02, 5] }        # linspace(start, stop, n)
    "tip.bending_length" = { values = [4.0, 5.0] }
    "coil.outer_diameter" = { lhs = [0.75, 0.9] } # sampled on a seeded Latin hypercube

Grid and value parameters form a full factorial; Latin-hypercube parameters
form one sample of ``n`` points; when both are present every factorial point
is combined with the whole sample.
"""

from __future__ import annotations

import hashlib
import json
import logging
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from softcath import design
from softcath.core.deprecation import renamed_keyword
from softcath.core.errors import DesignError
from softcath.core.limits import check_pressure
from softcath.design import presets
from softcath.design.load_cases import LOADS
from softcath.fem.section_model.api import COIL_BENDING
from softcath.fem.section_model.mesh import MESHERS
from softcath.models.options import check_tier_options
from softcath.studies.sweep.parameters import (
    Parameter,
    _design_count,
    _n_samples,
    _parameters,
    _real,
)
from softcath.studies.tiers import TIERS, tier_name

__all__ = ["Parameter", "SweepSpec", "load_spec", "parse_spec"]

log = logging.getLogger(__name__)

EVALUATORS = tuple(TIERS)
#: Evaluator -> the name the fingerprint hashes: the spelling of the sweeps written before the
#: tier names, so a sweep directory from then still resumes under the new names.
_FINGERPRINT_NAMES = {"paper": "analytic", "fem-nonlinear": "nonlinear"}
#: Designs per task at most when the section model runs (~13 ms a design: a few seconds a task).
#: Larger tasks share template kernels between more designs and cut the sweep process's share
#: (measured: ~1 ms a design with tasks of 25, ~0.2 with 250). A sweep written with other tasks
#: resumes with its recorded task size (:func:`softcath.studies.sweep.run_sweep`).
SECTION_CHUNK = 500
#: Tasks a section sweep is cut into at least, so every worker stays busy to the end; tasks are
#: not cut below :data:`SECTION_MIN_CHUNK` designs for it.
SECTION_TASKS = 16
SECTION_MIN_CHUNK = 25
#: Designs per task at most with the finite-strain section model (~75 ms of CPU a design on its
#: template path: ~10 s a task). Measured through the sweep: 74.4 ms of worker CPU a design with
#: tasks of 8, 71.0 with tasks of 125 (fewer task hand-overs, templates shared by more designs).
SECTION_NONLINEAR_CHUNK = 125
#: Designs per finite-strain task at least, when a small sweep is cut into :data:`SECTION_TASKS`.
SECTION_NONLINEAR_MIN_CHUNK = 8
_SWEEP_KEYS = {
    "name",
    "base",
    "pressures_MPa",
    "loads",
    "evaluators",
    "seed",
    "chunk_size",
    "fem",
    "feasibility",
    "section",
    "options",
}
_TOP_KEYS = {"sweep", "parameters", "sample"}


@renamed_keyword(old="pressures_MPa", new="pressures")
@dataclass(frozen=True)
class SweepSpec:
    """A parsed, checked sweep specification (see module docstring).

    Attributes
    ----------
    name
        Label of the sweep.
    base
        The base design reference as written (preset name or path).
    base_table
        The base design's TOML table structure (validated).
    parameters
        The swept parameters, in file order.
    pressures
        Pressures at which every design is evaluated [MPa], ascending (the spec file's key
        ``pressures_MPa``; that spelling of the keyword and attribute is deprecated).
    loads
        Load cases (``"cap"``, ``"lumen"``).
    evaluators
        Tier names (:data:`softcath.studies.tiers.TIERS`) from ``("paper", "section",
        "section-nonlinear", "fem", "fem-nonlinear")``: the paper's formula always runs;
        ``section-nonlinear`` is the finite-strain section model (~1 s per design and load).
    n_samples
        Latin-hypercube sample size (0 when no parameter is ``lhs``).
    seed
        Seed of the Latin hypercube.
    chunk_size
        Designs per task for analytic-only sweeps.
    mesh_size
        FEM mesh size [mm] or ``None`` for the FEM default.
    max_strain
        Silicone strain limit for the feasibility flag [-].
    section_mesh_size, section_coil_bending, section_mesher
        Section-model options (``[sweep.section]``; ``None`` = the model's default).
    options
        Tier name -> its options (``[sweep.options.<tier>]``, any of the tier's
        :attr:`~softcath.models.Tier.options`; only the tiers given).
    """

    name: str
    base: str
    base_table: dict
    parameters: tuple[Parameter, ...]
    pressures: tuple[float, ...]
    loads: tuple[str, ...]
    evaluators: tuple[str, ...]
    n_samples: int = 0
    seed: int = 0
    chunk_size: int = 500
    mesh_size: float | None = None
    max_strain: float = 0.3
    section_mesh_size: float | None = None
    section_coil_bending: str | None = None
    section_mesher: str | None = None
    options: dict = field(default_factory=dict)
    source: str = field(default="<string>", compare=False)

    @property
    def uses_fem(self) -> bool:
        """Whether a slow tier runs (the 3-D FEM: minutes a design)."""
        return any(TIERS[e].slow for e in self.evaluators)

    @property
    def uses_section(self) -> bool:
        """Whether a tier on the 2-D section mesh runs (``[sweep.section]`` is its table)."""
        return any(TIERS[e].section_mesh for e in self.evaluators)

    @property
    def section_options(self) -> dict:
        """Keyword options for ``softcath.fem.section_model.section_model`` (only those set)."""
        opts = {
            "mesh_size": self.section_mesh_size,
            "coil_bending": self.section_coil_bending,
            "mesher": self.section_mesher,
        }
        return {k: v for k, v in opts.items() if v is not None}

    @property
    def p_max(self) -> float:
        return max(self.pressures)

    def fingerprint(self) -> str:
        """A hash of everything that decides the designs and their results (not the run options)."""
        payload = {
            "base_table": self.base_table,
            "parameters": [(p.path, p.kind, list(p.values), p.bounds) for p in self.parameters],
            "pressures_MPa": self.pressures,
            "loads": self.loads,
            "evaluators": tuple(_FINGERPRINT_NAMES.get(e, e) for e in self.evaluators),
            "n_samples": self.n_samples,
            "seed": self.seed,
            "chunk_size": self.effective_chunk_size,
            "mesh_size": self.mesh_size,
            "max_strain": self.max_strain,
        }
        if self.uses_section:  # only then: sweeps written before the section evaluator keep their hash
            payload["section"] = self.section_options
        if self.options:  # only then: sweeps without tier options keep their hash
            payload["options"] = self.options
        text = json.dumps(payload, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @property
    def n_designs(self) -> int:
        """Designs of the sweep: the factorial grid times the Latin-hypercube sample (if any)."""
        return _design_count(self.parameters, self.n_samples)

    @property
    def effective_chunk_size(self) -> int:
        """Designs per task: one when FEM runs (each FEM design is saved as it completes); with the
        section model at most :data:`SECTION_CHUNK`, and few enough for :data:`SECTION_TASKS` tasks
        (but not below :data:`SECTION_MIN_CHUNK`)."""
        if self.uses_fem:
            return 1
        tasks = -(-self.n_designs // SECTION_TASKS)
        if any(not TIERS[e].linear for e in self.evaluators):  # the finite-strain section model
            return min(self.chunk_size, SECTION_NONLINEAR_CHUNK, max(SECTION_NONLINEAR_MIN_CHUNK, tasks))
        if not self.uses_section:
            return self.chunk_size
        balanced = max(SECTION_MIN_CHUNK, tasks)
        return min(self.chunk_size, SECTION_CHUNK, balanced)

    def to_json(self) -> dict:
        doc = {
            "name": self.name,
            "base": self.base,
            "parameters": [
                {"path": p.path, "kind": p.kind, "values": list(p.values), "bounds": p.bounds}
                for p in self.parameters
            ],
            "pressures_MPa": list(self.pressures),
            "loads": list(self.loads),
            "evaluators": list(self.evaluators),
            "n_samples": self.n_samples,
            "seed": self.seed,
            "chunk_size": self.effective_chunk_size,
            "mesh_size": self.mesh_size,
            "max_strain": self.max_strain,
            "section": self.section_options,
            "fingerprint": self.fingerprint(),
        }
        if self.options:
            doc["options"] = self.options
        return doc


def _base_table(base: str, spec_dir: Path) -> dict:
    """The base design's TOML tables exactly as written (so dotted paths match the file)."""
    if base in presets.names():
        table = tomllib.loads(presets.text(base))
    else:
        path = Path(base)
        if not path.is_absolute():
            path = spec_dir / path
        if not path.is_file():
            raise DesignError(
                "sweep.base",
                base,
                f"must be a preset ({', '.join(presets.names())}) or an existing .toml file",
            )
        try:
            table = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise DesignError("sweep.base", base, f"is not valid TOML: {exc}") from None
    design.from_dict(table)  # the base itself must be valid
    return table


def parse_spec(data: dict, *, spec_dir: str | Path = ".", source: str = "<string>") -> SweepSpec:
    """Check a sweep specification's tables and build a :class:`SweepSpec`."""
    sweep = _sweep_table(data)
    base = sweep.get("base", "paper")
    if not isinstance(base, str):
        raise DesignError("sweep.base", base, "must be a preset name or a path")
    base_table = _base_table(base, Path(spec_dir))
    ps = _pressures(sweep)
    loads, evals = _loads_and_evaluators(sweep)
    seed, chunk = _seed_and_chunk(sweep)
    mesh_size = _fem_mesh_size(sweep)
    section_mesh, coil_bending, mesher = _section_table(sweep.get("section", {}))
    options = check_tier_options(sweep.get("options"), parameter="sweep.options", tiers=evals)
    max_strain = _max_strain(sweep)
    params = _parameters(data, base_table)
    n_samples = _n_samples(data, params)
    name = sweep.get("name", Path(source).stem if source != "<string>" else "sweep")
    return SweepSpec(
        name=str(name),
        base=base,
        base_table=base_table,
        parameters=params,
        pressures=ps,
        loads=loads,
        evaluators=evals,
        n_samples=n_samples,
        seed=seed,
        chunk_size=chunk,
        mesh_size=None if mesh_size is None else float(mesh_size),
        max_strain=max_strain,
        section_mesh_size=section_mesh,
        section_coil_bending=coil_bending,
        section_mesher=mesher,
        options=options,
        source=source,
    )


def _sweep_table(data: dict) -> dict:
    """The ``[sweep]`` table, after checking the top-level tables' and its keys' names."""
    for key in data:
        if key not in _TOP_KEYS:
            raise DesignError(key, data[key], f"unknown table; allowed: {', '.join(sorted(_TOP_KEYS))}")
    sweep = data.get("sweep")
    if not isinstance(sweep, dict):
        raise DesignError("sweep", sweep, "table is required")
    for key in sweep:
        if key not in _SWEEP_KEYS:
            raise DesignError(
                f"sweep.{key}", sweep[key], f"unknown key; allowed: {', '.join(sorted(_SWEEP_KEYS))}"
            )
    return sweep


def _pressures(sweep: dict) -> tuple[float, ...]:
    """``sweep.pressures_MPa``, sorted and deduplicated, in [0, the one pressure bound]."""
    pressures = sweep.get("pressures_MPa")
    if not isinstance(pressures, list) or not pressures:
        raise DesignError("sweep.pressures_MPa", pressures, "must be a non-empty list of pressures [MPa]")
    ps = tuple(sorted({_real("sweep.pressures_MPa", p) for p in pressures}))
    if ps[0] < 0:
        raise DesignError("sweep.pressures_MPa", ps[0], "must be >= 0")
    check_pressure(ps[-1], param="sweep.pressures_MPa")
    return ps


def _loads_and_evaluators(sweep: dict) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """``sweep.loads`` and ``sweep.evaluators`` (tier names; ``paper`` always), in canonical order."""
    loads = sweep.get("loads", ["cap", "lumen"])
    if not isinstance(loads, list) or not loads or any(x not in LOADS for x in loads):
        raise DesignError("sweep.loads", loads, f"must be a non-empty list from {list(LOADS)}")
    evaluators = sweep.get("evaluators", ["paper"])
    if not isinstance(evaluators, list) or not evaluators:
        raise DesignError("sweep.evaluators", evaluators, f"must be a non-empty list from {list(EVALUATORS)}")
    evaluators = [tier_name(x, parameter="sweep.evaluators") for x in evaluators]
    evals = tuple(e for e in EVALUATORS if e in evaluators or TIERS[e].closed_form)  # the formula always
    return tuple(x for x in LOADS if x in loads), evals


def _seed_and_chunk(sweep: dict) -> tuple[int, int]:
    """``sweep.seed`` (>= 0) and ``sweep.chunk_size`` (>= 1)."""
    seed = sweep.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise DesignError("sweep.seed", seed, "must be an integer >= 0")
    chunk = sweep.get("chunk_size", 500)
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise DesignError("sweep.chunk_size", chunk, "must be an integer >= 1")
    return seed, chunk


def _fem_mesh_size(sweep: dict):
    """``sweep.fem.mesh_size`` as given (> 0 mm), or ``None``."""
    fem = sweep.get("fem", {})
    if not isinstance(fem, dict) or set(fem) - {"mesh_size"}:
        raise DesignError("sweep.fem", fem, "must be a table with only mesh_size [mm]")
    mesh_size = fem.get("mesh_size")
    if mesh_size is not None and _real("sweep.fem.mesh_size", mesh_size) <= 0:
        raise DesignError("sweep.fem.mesh_size", mesh_size, "must be > 0 mm")
    return mesh_size


def _max_strain(sweep: dict) -> float:
    """``sweep.feasibility.max_strain`` (> 0, default 0.3)."""
    feas = sweep.get("feasibility", {})
    if not isinstance(feas, dict) or set(feas) - {"max_strain"}:
        raise DesignError("sweep.feasibility", feas, "must be a table with only max_strain")
    max_strain = _real("sweep.feasibility.max_strain", feas.get("max_strain", 0.3))
    if max_strain <= 0:
        raise DesignError("sweep.feasibility.max_strain", max_strain, "must be > 0")
    return max_strain


def _section_table(table: Any) -> tuple[float | None, str | None, str | None]:
    """``[sweep.section]``: mesh_size [mm], coil_bending and mesher, all optional."""
    allowed = {"mesh_size", "coil_bending", "mesher"}
    if not isinstance(table, dict) or set(table) - allowed:
        raise DesignError("sweep.section", table, f"must be a table with only {', '.join(sorted(allowed))}")
    mesh = table.get("mesh_size")
    if mesh is not None and not 0.005 <= _real("sweep.section.mesh_size", mesh) <= 0.5:
        raise DesignError("sweep.section.mesh_size", mesh, "must be in [0.005, 0.5] mm")
    bending = table.get("coil_bending")
    if bending is not None and bending not in COIL_BENDING:
        raise DesignError("sweep.section.coil_bending", bending, f"must be one of {list(COIL_BENDING)}")
    mesher = table.get("mesher")
    if mesher is not None and mesher not in MESHERS:
        raise DesignError("sweep.section.mesher", mesher, f"must be one of {list(MESHERS)}")
    return (None if mesh is None else float(mesh)), bending, mesher


def load_spec(path: str | Path) -> SweepSpec:
    """Read and check a sweep specification TOML file."""
    path = Path(path)
    if not path.is_file():
        raise DesignError("spec", str(path), "does not exist")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise DesignError("spec", str(path), f"is not valid TOML: {exc}") from None
    return parse_spec(data, spec_dir=path.parent, source=str(path))
