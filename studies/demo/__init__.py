"""``softcath demo``: the paper's design end to end, in one ``DIR/index.html`` that tells the story.

The demo is a list of independent sections (:data:`SECTIONS`), one module
each. Each is a function ``fn(ctx) -> SectionOutput`` that writes its files
under ``ctx.out_dir`` and returns an HTML fragment. A section whose dependency
is not installed returns a clear "not available" note; a section that raises
is reported as failed with the reason, and the others still run. New
capabilities join the demo by adding a section. :mod:`.runner` puts the
fragments together into ``index.html`` (one ``<h2 id=KEY>`` per section).

Story: 1. the paper's model (:mod:`.model`: geometry as assembled, composite
beam, cap vs lumen load); 2. three tiers (:mod:`.tiers`): the paper's formula,
the 2-D section model and the 3-D FEM under both loads (with a rotatable 3-D
view of the deformed tip), and κ/p against the silicone's ν; 3. large bends
(:mod:`.large_bends`): the finite-strain FEM against the linear one, and the
silicone strain; 4. what the measured data add (:mod:`.calibration`, eq. 8);
5. which missing effect the data point to (:mod:`.effects`); 6. a small sweep
on the section model, the chosen design checked by the 3-D FEM (:mod:`.sweep`);
7. the design to build (:mod:`.verdict`).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from softcath.studies.demo.calibration import section_calibration
from softcath.studies.demo.context import DEMO_MAX_STRAIN, DEMO_PRESSURES_MPA, DemoContext, SectionOutput
from softcath.studies.demo.effects import section_effects
from softcath.studies.demo.large_bends import DEMO_LARGE_BEND_PRESSURES_MPA, section_large_bends
from softcath.studies.demo.model import section_model
from softcath.studies.demo.prototype import section_prototype
from softcath.studies.demo.runner import DemoResult, default_data, run_sections
from softcath.studies.demo.sweep import DEMO_SELECT_PRESSURE_MPA, demo_sweep_spec, section_sweep
from softcath.studies.demo.tiers import section_tiers
from softcath.studies.demo.verdict import section_verdict

__all__ = [
    "DemoContext",
    "SectionOutput",
    "SECTIONS",
    "run_demo",
    "default_data",
    "DEMO_PRESSURES_MPA",
    "demo_sweep_spec",
    "DEMO_MAX_STRAIN",
    "DEMO_LARGE_BEND_PRESSURES_MPA",
    "DEMO_SELECT_PRESSURE_MPA",
    "DemoResult",
    "section_model",
    "section_tiers",
    "section_large_bends",
    "section_calibration",
    "section_effects",
    "section_prototype",
    "section_sweep",
    "section_verdict",
]

SECTIONS: list[tuple[str, str, Callable[[DemoContext], SectionOutput]]] = [
    ("model", "1. The paper's model", section_model),
    ("fem", "2. Three tiers: the paper's formula, the section model, the 3-D FEM", section_tiers),
    ("large_bends", "3. Large bends: finite-strain FEM", section_large_bends),
    ("calibration", "4. What the measured data add: calibration (eq. 8)", section_calibration),
    ("effects", "5. The missing effect", section_effects),
    ("prototype", "6. A built prototype, point by point", section_prototype),
    ("sweep", "7. A small sweep", section_sweep),
    ("verdict", "8. Which design to build", section_verdict),
]


def run_demo(
    out_dir: str | Path,
    *,
    design_ref: str = "paper",
    data_csv: str | Path | None = None,
    workers: int = 2,
    only: tuple[str, ...] | None = None,
    progress: bool = True,
    fem: bool = True,
    options=None,
) -> DemoResult:
    """Run the demo sections (:data:`SECTIONS`, read at call time) into ``out_dir``.

    The parameters are those of :func:`.runner.run_sections`, which documents them.
    """
    return run_sections(
        SECTIONS,
        out_dir,
        design_ref=design_ref,
        data_csv=data_csv,
        workers=workers,
        only=only,
        progress=progress,
        fem=fem,
        options=options,
    )
