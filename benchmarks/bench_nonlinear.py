"""Finite-strain solver side by side with FElupe: same geometry, material and follower pressure.

A silicone cantilever (1 x 1 x 10 mm, decoupled neo-Hookean μ = 0.85 MPa,
κ = 8.2 MPa, i.e. E = 2.46 MPa, ν = 0.45) clamped at z = 0 is bent by a
follower pressure on its +y face to a large tip rotation. Both codes walk the
same load steps with Newton and report the rotation of the tip section
(Kabsch fit, the same post-processing for both) and the wall time.

Mesh: FElupe 11 has follower-pressure boundary regions for hexahedra only, so
FElupe runs quadratic (20-node) hexahedra on an n x n x m grid and softcath
runs P2 tetrahedra on the same grid (each hexahedron split into six
tetrahedra, the same vertices) — the same mesh up to the element shape.
FElupe is a benchmark peer only, not a runtime dependency.

Timing: each code first solves a tiny problem untimed (library loading, MKL's
first call, NumPy's einsum paths), then the two codes run alternately
``--repeat`` times and the best time of each is compared, so neither pays the
other's start-up nor a burst of load from another process.

Run::

    python benchmarks/bench_nonlinear.py [--cells 3 --length-cells 20 --pressure 0.001 --steps 5 --repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from softcath.fem.hyperelastic.laws import neo_hookean  # noqa: E402
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody  # noqa: E402
from softcath.fem.nonlinear.meshes import box, dofs_of_facets, facets_where  # noqa: E402
from softcath.fem.nonlinear.newton import solve  # noqa: E402
from softcath.fem.nonlinear.post import bend_angles  # noqa: E402

E, NU = 2.46, 0.45
MU, KAPPA = E / (2 * (1 + NU)), E / (3 * (1 - 2 * NU))
H, L = 1.0, 10.0


def run_softcath(n: int, m: int, pressure: float, steps: int) -> tuple[float, float, int]:
    t0 = time.perf_counter()
    mesh = box(size=(H, H, L), cells=(n, n, m))
    body = HyperelasticBody(
        mesh, np.zeros(mesh.t.shape[1], int), {0: neo_hookean(shear_modulus=MU, bulk_modulus=KAPPA)}
    )
    press = FollowerPressure(body, facets_where(mesh, lambda x: x[1] > H / 2 - 1e-9))
    fixed = dofs_of_facets(body.basis, facets_where(mesh, lambda x: x[2] < 1e-9))
    res = solve(body, fixed_dofs=fixed, loads=[(press, pressure)], steps=steps)
    end = np.isclose(body.nodes[:, 2], L)
    theta = float(bend_angles(body.nodes, res.displacements, end)[-1])
    return theta, time.perf_counter() - t0, body.ndofs


def run_felupe(n: int, m: int, pressure: float, steps: int) -> tuple[float, float, int]:
    import felupe as fe

    t0 = time.perf_counter()
    mesh = fe.Cube(a=(-H / 2, -H / 2, 0), b=(H / 2, H / 2, L), n=(n + 1, n + 1, m + 1))
    mesh = fe.mesh.convert(mesh, order=2)
    region = fe.RegionQuadraticHexahedron(mesh)
    field = fe.FieldContainer([fe.Field(region, dim=3)])
    solid = fe.SolidBody(fe.NeoHooke(mu=MU, bulk=KAPPA), field)
    top = fe.RegionQuadraticHexahedronBoundary(mesh, mask=np.isclose(mesh.points[:, 1], H / 2))
    field_top = fe.FieldContainer([fe.Field(top, dim=3)])
    field_top.link(field)
    press = fe.SolidBodyPressure(field=field_top)
    clamp = fe.Boundary(field[0], fz=0.0)
    step = fe.Step(
        items=[solid, press],
        ramp={press: pressure * fe.math.linsteps([0, 1], num=steps)},
        boundaries={"clamp": clamp},
    )
    disp = []
    job = fe.Job(steps=[step], callback=lambda i, j, res: disp.append(res.x[0].values.copy()))
    job.evaluate(tol=1e-8)
    pts = mesh.points
    end = np.isclose(pts[:, 2], L)
    theta = float(bend_angles(pts, np.stack(disp), end)[-1])
    return theta, time.perf_counter() - t0, field[0].values.size


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=3)
    ap.add_argument("--length-cells", type=int, default=20)
    ap.add_argument(
        "--pressure", type=float, default=0.001, help="MPa on the +y face (0.001: ~40 deg tip rotation)"
    )
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each code (best is reported)")
    a = ap.parse_args(argv)
    run_softcath(1, 2, a.pressure, 1)  # warm-up, untimed
    run_felupe(1, 2, a.pressure, 1)
    times_s, times_f = [], []
    for _ in range(max(1, a.repeat)):
        th_s, t, n_s = run_softcath(a.cells, a.length_cells, a.pressure, a.steps)
        times_s.append(t)
        th_f, t, n_f = run_felupe(a.cells, a.length_cells, a.pressure, a.steps)
        times_f.append(t)
    t_s, t_f = min(times_s), min(times_f)
    print(
        f"cantilever {H}x{H}x{L} mm, neo-Hookean E={E} nu={NU}, follower pressure {a.pressure} MPa, "
        f"{a.steps} load steps"
    )
    print(f"softcath (P2 tets):      bend angle {np.degrees(th_s):8.3f} deg  time {t_s:7.2f} s  DOFs {n_s}")
    print(f"FElupe   (Q2 hexahedra): bend angle {np.degrees(th_f):8.3f} deg  time {t_f:7.2f} s  DOFs {n_f}")
    print(
        f"all runs [s]: softcath {', '.join(f'{t:.2f}' for t in times_s)}; "
        f"FElupe {', '.join(f'{t:.2f}' for t in times_f)}"
    )
    print(
        f"angle ratio softcath/FElupe = {th_s / th_f:.4f} (target within 2 %); "
        f"time ratio softcath/FElupe = {t_s / t_f:.2f} (target <= 1)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
