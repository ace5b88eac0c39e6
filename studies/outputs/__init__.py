"""What a command writes, written by the library: one module per command's result files.

Each module composes one command's result files (JSON, CSV, figures) from the library's
results, so that what ``softcath COMMAND`` writes is what a script calling the same
function writes, byte for byte. Modules: ``tables`` (the CSV number format), ``analytic``
(``analytic.csv/.json/.png``), ``section`` (``section.json/.csv/.png`` and the coil-bound
curve), ``overlay`` (several designs' bend curves), ``fem_check`` (the FEM check's
``fem.json`` with the paper's formula beside the 3-D answer), ``predict``
(``prediction.json``, ``samples.csv``, the band figures), ``selection`` (``selection.json``
and the chosen designs), ``optimum`` (an optimisation's record, designs and report) and
``discrepancy`` (the missing-effect record and page, the prototype record).
"""
