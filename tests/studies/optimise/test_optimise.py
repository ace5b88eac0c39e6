"""softcath.studies.optimise: known optima of the paper's formula, seeds, invalid designs, backends, the FEM
re-check."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import brentq

from softcath import analytic
from softcath.design import presets
from softcath.design.errors import DesignError
from softcath.studies.optimise import make_problem, make_robustness, optimise
from softcath.studies.predict.ranges import Range
from softcath.studies.sweep.variants import build_variant

E_TUBE = "materials.medical_silicone_tubing.youngs_modulus"
BEND = "maximise bend_angle_deg at p=0.5"


@pytest.fixture(scope="module")
def table():
    return tomllib.loads(presets.text("paper"))


def _bend_deg(table, overrides) -> float:
    """The paper's formula (cap load) at 0.5 MPa, straight from the analytic model."""
    r = analytic.response(build_variant(table, overrides), np.array([0.5]), load="cap")
    return math.degrees(float(np.asarray(r.bend_angle)[0]))


def test_active_bound(table):
    """Bending grows as the tube softens: the optimum is the lower modulus bound."""
    p = make_problem(table, variables=[f"{E_TUBE}=1:4"], objectives=[BEND], model="paper", load="cap")
    best = optimise(p, budget=60, seed=3, progress=False).best[0]
    assert best.parameters[E_TUBE] == pytest.approx(1.0, rel=0.01)
    assert best.objectives[BEND] == pytest.approx(_bend_deg(table, {E_TUBE: 1.0}), rel=0.01)


def test_active_constraint(table):
    """Maximise the bend under a cap on it: the modulus where the cap is met exactly (root of the formula)."""
    p = make_problem(
        table,
        variables=[f"{E_TUBE}=1:4"],
        objectives=[BEND],
        constraints=["bend_angle_deg <= 10 at p=0.5"],
        model="paper",
        load="cap",
    )
    opt = optimise(p, budget=80, seed=1, progress=False)
    best = opt.best[0]
    e_star = brentq(lambda e: _bend_deg(table, {E_TUBE: e}) - 10.0, 1.0, 4.0, xtol=1e-10)
    assert best.feasible and best.constraints["bend_angle_deg <= 10 at p=0.5"] >= 0
    assert best.parameters[E_TUBE] == pytest.approx(e_star, rel=0.01)
    assert best.objectives[BEND] == pytest.approx(10.0, rel=0.01)
    assert opt.evaluations <= 80


def test_same_seed_same_result_and_invalid_designs_are_violations(table):
    """A lumen offset range much of which cannot be built: no crash, a buildable winner, reproducible."""
    p = make_problem(
        table, variables=["tube.h=-0.3:0.3", f"{E_TUBE}=1:4"], objectives=[BEND], model="paper", load="cap"
    )
    a = optimise(p, budget=60, seed=5, progress=False)
    b = optimise(p, budget=60, seed=5, progress=False)
    assert a.best == b.best
    assert (~a.history["ok"]).any(), "the range should include designs that cannot be built"
    assert a.best[0].feasible
    build_variant(table, a.best[0].parameters)  # buildable


def test_pareto_set_is_nondominated(table):
    p = make_problem(
        table,
        variables=["tube.h=-0.03:0.03", f"{E_TUBE}=1:4"],
        objectives=[BEND, "minimise max_strain at p=0.5"],
        model="paper",
        load="cap",
    )
    opt = optimise(p, budget=80, seed=2, progress=False)
    assert opt.algorithm.startswith("NSGA-II") and len(opt.best) >= 2
    f = np.array([[-w.objectives[BEND], w.objectives["minimise max_strain at p=0.5"]] for w in opt.best])
    for i in range(len(f)):
        assert not np.any(np.all(f <= f[i], axis=1) & np.any(f < f[i], axis=1))


def test_robust_constraint_holds_with_probability(table):
    """Robust: the winner meets its cap on at least P of the silicone lots, and is reported with
    p5/p50/p95."""
    ranges = [
        Range(E_TUBE.replace("medical_silicone_tubing", "ecoflex_00_30"), low=0.05, high=0.2),
        Range("materials.medical_silicone_tubing.poisson_ratio", low=0.45, high=0.49),
    ]
    rob = make_robustness(0.9, ranges, samples=20, seed=0)
    p = make_problem(
        table,
        variables=[f"{E_TUBE}=1:4"],
        objectives=[BEND],
        constraints=["bend_angle_deg <= 10 at p=0.5"],
        model="paper",
        load="cap",
    )
    best = optimise(p, budget=60, seed=0, robust=rob, progress=False).best[0]
    cons = "bend_angle_deg <= 10 at p=0.5"
    assert best.probabilities[cons] >= 0.9
    pct = best.percentiles[BEND]
    assert pct["p5"] <= pct["p50"] <= pct["p95"]
    assert pct["p50"] < 10.0  # the nominal optimum would sit on the cap


def test_finite_strain_model_optimises_on_its_own_bend(table):
    """The finite-strain section model as the optimiser's model: an active bound (a softer tube bends
    more) whose objective is the finite-strain curve's own bend of the winner."""
    from softcath.fem.section_model.finite_strain import section_curve

    p = make_problem(table, variables=[f"{E_TUBE}=1.5:4"], objectives=[BEND], model="section-nonlinear")
    best = optimise(p, budget=10, seed=2, progress=False).best[0]
    assert best.parameters[E_TUBE] == pytest.approx(1.5, rel=0.05)
    c = section_curve(build_variant(table, best.parameters), [0.5])
    assert best.objectives[BEND] == pytest.approx(math.degrees(c.bend_angle_rad[0]), rel=1e-6)


def test_bad_bounds_are_named(table):
    with pytest.raises(DesignError, match=r"vary.tube.h.high = -0.1: must be > low = 0.1"):
        make_problem(table, variables=["tube.h=0.1:-0.1"], objectives=[BEND])
    with pytest.raises(DesignError, match="vary.tube.nope.*not a field"):
        make_problem(table, variables=["tube.nope=0:1"], objectives=[BEND])
    with pytest.raises(DesignError, match="budget = 3"):
        p = make_problem(table, variables=[f"{E_TUBE}=1:4"], objectives=[BEND], model="paper")
        optimise(p, budget=3, progress=False)


@pytest.mark.slow
def test_dask_local_cluster_equals_local_processes(table):
    """A 2-worker Dask LocalCluster on loopback finds exactly what 2 local processes find."""
    from distributed import LocalCluster

    p = make_problem(
        table,
        variables=["tube.h=-0.04:0.04"],
        objectives=["maximise bend_angle_deg at p=0.5"],
        constraints=["max_strain <= 0.3 at p=0.5"],
        model="section",
    )
    local = optimise(p, budget=12, seed=4, workers=2, progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None) as cluster:
        remote = optimise(p, budget=12, seed=4, scheduler=cluster.scheduler_address, progress=False)
    assert remote.backend.startswith("dask(tcp://127.0.0.1:")
    assert remote.best == local.best
    assert remote.history.drop(columns="reason").equals(local.history.drop(columns="reason"))


@pytest.mark.slow
def test_section_model_beats_a_grid_four_times_its_budget(table):
    """Section model, two shape variables: 30 optimiser evaluations vs the best of an 11 x 11 grid (121)."""
    from softcath.studies.optimise import Backend, evaluate_parameters

    obj, cons = "maximise bend_angle_deg at p=0.5", "max_strain <= 0.45 at p=0.5"
    p = make_problem(
        table,
        variables=["tube.h=-0.04:0.04", "tube.a_int=0.07:0.13"],
        objectives=[obj],
        constraints=[cons],
        model="section",
    )
    opt = optimise(p, budget=30, seed=0, workers=2, progress=False)
    grid = [
        {"tube.h": h, "tube.a_int": a}
        for h in np.linspace(-0.04, 0.04, 11)
        for a in np.linspace(0.07, 0.13, 11)
    ]
    with Backend(workers=2) as backend:
        s = evaluate_parameters(p, grid, backend)
    feasible = s.ok & (s.margins[:, 0] >= 0)
    grid_best = float(np.max(s.objectives[feasible, 0]))
    assert opt.best[0].feasible
    assert opt.best[0].objectives[obj] >= grid_best - 1e-9


@pytest.mark.slow
def test_winner_rechecked_by_the_3d_fem(table):
    """The 3-D linear FEM re-check of a section-model winner agrees to a few percent."""
    from softcath.studies.sweep import fem_check_function

    if fem_check_function() is None:
        pytest.skip("fem.check not importable in this build")
    p = make_problem(
        table,
        variables=["tube.h=-0.02:0.02"],
        objectives=["maximise bend_angle_deg at p=0.5"],
        model="section",
    )
    best = optimise(p, budget=10, seed=0, fem_check=True, progress=False).best[0]
    check = best.fem_check
    assert check["status"] == "ok", check["reason"]
    assert check["curvature_rel_diff"] < 0.05
    assert check["objectives"]["maximise bend_angle_deg at p=0.5"] == pytest.approx(
        best.objectives["maximise bend_angle_deg at p=0.5"], rel=0.05
    )


def test_robust_range_on_a_design_variable_is_left_out(table):
    ranges = [
        Range(E_TUBE, low=1.6, high=4.4),
        Range("materials.ecoflex_00_30.youngs_modulus", low=0.05, high=0.2),
    ]
    rob = make_robustness(0.5, ranges, samples=4, seed=0)
    p = make_problem(table, variables=[f"{E_TUBE}=1:4"], objectives=[BEND], model="paper", load="cap")
    opt = optimise(p, budget=20, seed=0, robust=rob, progress=False)
    assert [r["path"] for r in opt.robust["ranges"]] == ["materials.ecoflex_00_30.youngs_modulus"]
    assert opt.best[0].parameters[E_TUBE] == pytest.approx(1.0, rel=0.01)
