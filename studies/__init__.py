"""Studies over designs and data: sweeps, reports, selection, discrepancy, prediction bands, the demo.

Sub-packages: ``sweep`` (specs, runner, evaluators, store, the merged results
table), ``report`` (the sweep's HTML report), ``discrepancy`` (the missing-effect
workflow over time series and over design sweeps), ``predict`` (prediction
bands); modules: ``selection``, ``coil_ranking``, ``atomic`` (whole-or-nothing
outputs), ``model_validity`` (range warnings and refusals), ``plots``, ``demo``.
"""

if __name__ != "softcath.studies":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.studies, not studies: the top-level folders are rooms of the softcath package"
    )
