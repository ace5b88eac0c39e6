"""The sweep's HTML report and the pages around it (offline, no network).

Modules: ``html_report`` (the sweep report, ``DIR/report/index.html``),
``figures`` (its PNGs), ``explore`` and ``interactive`` (the Plotly page
``explore.html``), ``optimum`` (the ``softcath optimise`` report) and
``html_blocks`` (the escaped building blocks every page is made of).

>>> from softcath.studies.report import write_report      # doctest: +SKIP
>>> write_report("out/quick")                               # doctest: +SKIP
"""

from __future__ import annotations

from softcath.studies.report.html_report import design_of, sweep_sections, write_report

__all__ = ["write_report", "sweep_sections", "design_of"]
