"""softcath: design, check and measure a hydraulically actuated soft micro-catheter tip.

Everything imports from this one namespace; each concept has its own room:

=========================  ====================================================
``softcath.design``        the tip as validated data, materials, CAD, measurement CSV
``softcath.analytic``      the paper's composite beam, pose, calibration, effects
``softcath.fem``           meshes, linear / finite-strain 3-D FEM, section model, coils
``softcath.studies``       sweeps, reports, selection, discrepancy, prediction bands
``softcath.hardware``      real devices: serial sensors, stage, recorder, tip vision
``softcath.virtualbench``  the simulated rig: plant, truth effects, virtual devices
``softcath.cli``           the ``softcath`` command line (the library never imports it)
=========================  ====================================================

Units are mm, N, MPa and s throughout.

>>> import softcath
>>> softcath.__version__
'0.2.0'
"""

__version__ = "0.2.0"

__all__ = ["__version__"]
