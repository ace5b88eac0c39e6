"""Benchmark of the FEM bending check, printed as ratios.

In one run, on the paper design:

1. cold (mesh + assemble + solve, empty cache) and warm (mesh from the cache)
   ``fem.check`` at the default mesh (0.16 mm: kappa within 1 % of its
   Richardson extrapolation, tests/fem/test_fem_tip.py); targets warm <= 15 s,
   cold <= 20 s on 2 cores;
2. our solver (PARDISO, SPD mode, factorise once) against scikit-fem's default
   ``solve`` (SciPy SuperLU via spsolve) on the same clamped system (target >= 5x);
   and our vectorised P2 assembly against scikit-fem's ``BilinearForm``;
3. time and peak memory over three mesh sizes (each in a fresh subprocess, so
   the peak RSS is that size's own);
4. the two meshers side by side (gmsh extrusion vs pytetwild) on mesh time.

Run: ``python benchmarks/bench_fem.py`` (``make bench``). ``--quick`` skips 3-4,
``--only-sizes`` runs only 3-4.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _cold_warm() -> None:
    from softcath import fem

    with tempfile.TemporaryDirectory() as cache:
        os.environ["SOFTCATH_CACHE"] = cache
        t = time.perf_counter()
        r = fem.check("paper", pressures=[0.1], loads=("cap", "lumen"))
        cold = time.perf_counter() - t
        t = time.perf_counter()
        w = fem.check("paper", pressures=[0.1], loads=("cap", "lumen"))
        warm = time.perf_counter() - t
    assert w.mesh_cached and not r.mesh_cached
    print(f"paper design, default mesh 0.16 mm: {r.dofs} dofs, {r.n_elements} tets, both loads")
    print(
        f"  cold {cold:6.1f} s (mesh {r.mesh_seconds:.1f}, assemble {r.assemble_seconds:.1f}, "
        f"solve {r.solve_seconds:.1f})   target <= 20 s  {'OK' if cold <= 20 else 'MISSED'}"
    )
    print(
        f"  warm {warm:6.1f} s (cache hit)                          target <= 15 s  "
        f"{'OK' if warm <= 15 else 'MISSED'}   cold/warm = {cold / warm:.2f}"
    )


def _solver_vs_skfem() -> None:
    import numpy as np
    import skfem
    from skfem.helpers import ddot, sym_grad

    from softcath import design
    from softcath.fem.adapter import fem_laws_from_design, geometry_from_design
    from softcath.fem.elasticity import ElasticProblem
    from softcath.fem.mesh import mesh_tip
    from softcath.fem.tags import tag_facets

    d = design.preset("paper")
    g = geometry_from_design(d)
    laws = fem_laws_from_design(d)
    m = mesh_tip(g, mesh_size=0.16)
    sk = m.skfem_mesh()
    tags = tag_facets(sk, g)
    t = time.perf_counter()
    pb = ElasticProblem(sk, m.labels, laws, [(tags["base"], (0, 1, 2))])
    t_ours_asm = time.perf_counter() - t
    f = pb.pressure_load(tags["cap"])
    # scikit-fem's own assembly of the same operator (per-region basis + BilinearForm)
    t = time.perf_counter()
    ev = skfem.ElementVector(skfem.ElementTetP2())
    k_ref = None
    for label, law in laws.items():
        cells = np.flatnonzero(m.labels == label)
        if cells.size == 0:
            continue
        c = law.tensor()
        basis = skfem.CellBasis(sk, ev, intorder=pb.intorder, elements=cells)

        @skfem.BilinearForm
        def form(u, v, w, c=c):
            return ddot(np.einsum("ijkl,kl...->ij...", c, sym_grad(u)), sym_grad(v))

        part = form.assemble(basis)
        k_ref = part if k_ref is None else k_ref + part
    t_skfem_asm = time.perf_counter() - t
    print(
        f"assembly, {pb.ndofs} dofs: ours {t_ours_asm:.2f} s, scikit-fem BilinearForm "
        f"{t_skfem_asm:.2f} s -> {t_skfem_asm / t_ours_asm:.1f}x"
    )
    kff = pb.stiffness[pb.free][:, pb.free].tocsr()
    t = time.perf_counter()
    u_ours = pb.solve(f).u.ravel()[pb.free]
    t_ours = time.perf_counter() - t
    t = time.perf_counter()
    u_ref = skfem.solve(kff, f[pb.free])
    t_ref = time.perf_counter() - t
    diff = np.abs(u_ours - u_ref).max() / np.abs(u_ref).max()
    print(
        f"solve, same system: ours (PARDISO SPD) {t_ours:.2f} s, skfem.solve (SuperLU) "
        f"{t_ref:.2f} s -> {t_ref / t_ours:.1f}x (target >= 5x); max rel diff {diff:.1e}"
    )
    # each further pressure or load case reuses the factorisation
    t = time.perf_counter()
    pb.solve(2.0 * f)
    print(f"  a further right-hand side on the same factorisation: {time.perf_counter() - t:.2f} s")


def _one_size(h: float) -> None:
    """Child process: mesh (no cache) + assemble + solve at size h; print JSON."""
    import resource

    from softcath import design
    from softcath.fem.adapter import fem_laws_from_design, geometry_from_design
    from softcath.fem.pipeline import run_tip

    d = design.preset("paper")
    t = time.perf_counter()
    sol = run_tip(
        geometry_from_design(d), fem_laws_from_design(d), loads=("cap",), mesh_size=h, use_cache=False
    )
    total = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        json.dumps(
            {
                "h": h,
                "dofs": int(sol.problem.ndofs),
                "total": total,
                "mesh": sol.mesh_seconds,
                "assemble": sol.assemble_seconds,
                "solve": sol.solve_seconds,
                "peak_mb": peak,
                "kappa": sol.fits["cap"].curvature_per_mm,
            }
        )
    )


def _sizes() -> None:
    print("cost vs size (fresh process each, no cache):")
    print("   h [mm]     dofs   total [s]  mesh  assemble  solve   peak RSS [MB]   kappa/p [1/mm/MPa]")
    rows = []
    for h in (0.24, 0.16, 0.11):
        out = subprocess.run(
            [sys.executable, __file__, "--size", str(h)],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
        )
        r = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append(r)
        print(
            f"   {r['h']:.2f}  {r['dofs']:9d}  {r['total']:8.1f}  {r['mesh']:5.1f}  "
            f"{r['assemble']:6.1f}  {r['solve']:6.1f}  {r['peak_mb']:10.0f}   {r['kappa']:.5f}"
        )
    import math

    a, b = rows[0], rows[-1]
    slope = math.log(b["solve"] / a["solve"]) / math.log(b["dofs"] / a["dofs"])
    print(f"  solve time grows as dofs^{slope:.2f} over this range")


def _meshers() -> None:
    from dataclasses import replace

    from softcath import design
    from softcath.fem.adapter import geometry_from_design
    from softcath.fem.mesh import mesh_tip

    # A 1.5 mm slice of the paper tip (same section, lumen, cap): pytetwild on the
    # full 5 mm takes many minutes on 2 shared cores.
    g = replace(geometry_from_design(design.preset("paper")), length=1.5)
    rows = []
    for mesher in ("gmsh", "tetwild"):
        t = time.perf_counter()
        m = mesh_tip(g, mesh_size=0.1, mesher=mesher, use_cache=False)
        rows.append((mesher, time.perf_counter() - t, m))
    print("meshers side by side (1.5 mm slice of the paper tip, size 0.1 mm, no cache):")
    for mesher, sec, m in rows:
        worst = max(abs(e) for e in m.volume_errors().values())
        print(
            f"  {mesher:8s}: {sec:7.1f} s, {m.quality.n_tets:7d} tets, "
            f"worst region volume error {100 * worst:.2f} %, min scaled Jacobian "
            f"{m.quality.min_scaled_jacobian:.3g}"
        )
    print(f"  tetwild / gmsh time: {rows[1][1] / rows[0][1]:.0f}x")


def main(argv: list[str]) -> int:
    if "--size" in argv:
        _one_size(float(argv[argv.index("--size") + 1]))
        return 0
    if "--only-sizes" not in argv:
        _cold_warm()
        _solver_vs_skfem()
    if "--quick" not in argv:
        _sizes()
        _meshers()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
