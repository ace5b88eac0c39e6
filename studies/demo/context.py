"""What the demo's sections share: the context, a section's output, the demo's constants."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from softcath.studies.report.html_blocks import esc, note

__all__ = ["DemoContext", "SectionOutput", "unavailable", "DEMO_PRESSURES_MPA", "DEMO_MAX_STRAIN"]

DEMO_PRESSURES_MPA = (0.5, 1.0, 2.0)  # the bundled bench data span 0–2 MPa
DEMO_MAX_STRAIN = 0.5


@dataclass
class DemoContext:
    """What the sections share: output directory, the design, and results earlier sections leave."""

    out_dir: Path
    design: object
    data_csv: Path
    workers: int = 2
    fem: bool = True
    #: Tier name -> its options (``--model-option``): the tiers' runs take them.
    options: dict = field(default_factory=dict)
    shared: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SectionOutput:
    """One section's HTML fragment and files; ``status`` is ``ok``, ``unavailable`` or ``failed``."""

    html: str
    files: tuple[Path, ...] = ()
    status: str = "ok"


def unavailable(what: str, why: str, *, lead: str = "Not available in this build") -> SectionOutput:
    """A section's "not available" (or "not run") note, with the reason."""
    return SectionOutput(note(f"<b>{esc(lead)}:</b> {esc(what)} ({esc(why)})."), status="unavailable")
