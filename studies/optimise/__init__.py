"""Design optimisation over design paths, with ``select``'s expressions as objectives and constraints.

One objective: pymoo's differential evolution, then a COBYLA polish; several:
NSGA-II (pymoo), giving the Pareto set. Candidates are evaluated by the
sweep's evaluators (the model tier by name), locally, in processes or on Dask;
``robust`` optimises the objectives' p50 over material and manufacturing
ranges with every constraint met at probability ≥ P. Winners can be
re-checked by the 3-D linear FEM.

Modules: ``problem`` (variables, expressions, model), ``scoring`` (objective
values and constraint margins from a results table), ``backend`` (where
evaluations run), ``evaluate`` (nominal and robust batches), ``search``
(pymoo, scipy), ``recheck`` (3-D FEM), ``result`` and ``workflow``.
"""

from __future__ import annotations

from softcath.studies.optimise.backend import Backend
from softcath.studies.optimise.evaluate import Robustness, Scores, evaluate_parameters, make_robustness
from softcath.studies.optimise.problem import MODELS, Problem, Variable, make_problem, parse_variable
from softcath.studies.optimise.result import Optimum, Winner
from softcath.studies.optimise.workflow import check_search, optimise, write_optimum

__all__ = [
    "MODELS",
    "Backend",
    "Optimum",
    "Problem",
    "Robustness",
    "Scores",
    "Variable",
    "Winner",
    "check_search",
    "evaluate_parameters",
    "make_problem",
    "make_robustness",
    "optimise",
    "parse_variable",
    "write_optimum",
]
