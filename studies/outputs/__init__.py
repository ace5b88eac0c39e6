"""What a command writes, written by the library: one module per result's files.

Each module composes one command's result files (JSON, CSV, figures) from the
library's results, so that what ``softcath COMMAND`` writes is what a script
calling the same function writes. Modules: ``tables`` (the CSV number format),
``analytic`` (``analytic.csv/.json/.png``), ``section`` (``section.json/.csv/.png``
and the coil-bound curve), ``overlay`` (several designs' bend curves), ``fem_check``
(the linear check's ``fem.json``, the paper's formula beside a 3-D answer),
``predict`` (``prediction.json``, ``samples.csv``, the band figures) and
``discrepancy`` (the prototype record).
"""
