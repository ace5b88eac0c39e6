"""3-D finite-strain assembly: the compiled element loop against the batched NumPy kernels.

The paper design's default 3-D mesh (section size 0.15 mm, 12 segments per circle, 12 layers:
the mesh ``softcath fem paper --nonlinear --pressure 0.6`` solves), mixed u–p, one internal-force
+ tangent assembly (``HyperelasticBody.internal``) at a bent state, timed for both paths in the
same run (the NumPy path is the baseline), best of ``--repeat``. The compiled kernel is called
once untimed first (JIT or on-disk cache load). Also printed: the largest difference between the
two paths relative to the largest entry, and the follower-pressure assembly for scale.

Run::

    python benchmarks/bench_nonlinear_assembly.py [--layers 12 --size 0.15 --curvature-points 12 --repeat 3]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _timing import best_of, row  # noqa: E402

from softcath import design  # noqa: E402
from softcath.fem.nonlinear.body import FollowerPressure, HyperelasticBody  # noqa: E402
from softcath.fem.nonlinear.catheter import catheter_laws, mesh_catheter  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--layers", type=int, default=12)
    ap.add_argument("--size", type=float, default=0.15)
    ap.add_argument("--curvature-points", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    d = design.preset("paper")
    cm = mesh_catheter(d, size=args.size, layers=args.layers, curvature_points=args.curvature_points)
    laws = catheter_laws(d)
    fast = HyperelasticBody(cm.mesh, cm.labels, laws, mixed=True, compiled=True)
    ref = HyperelasticBody(cm.mesh, cm.labels, laws, mixed=True, compiled=False)
    # a bent state: the tip's axis turned by ~50 deg over its length (rotation about x), so every
    # element sees a finite rotation and stretch, as in the 0.6 MPa solve
    x = fast.nodes
    kappa = np.deg2rad(50.0) / cm.length
    ang = kappa * x[:, 2]
    u = np.zeros_like(x)
    u[:, 1] = (1 - np.cos(ang)) / kappa + x[:, 1] * (np.cos(ang) - 1)
    u[:, 2] = np.sin(ang) / kappa - x[:, 1] * np.sin(ang) - x[:, 2]
    u = u.ravel()
    fast.internal(u)  # compile or load the cached machine code
    t_ref, (f0, d0) = best_of(lambda: ref.internal(u), args.repeat)
    t_fast, (f1, d1) = best_of(lambda: fast.internal(u), args.repeat)
    press = FollowerPressure(fast, cm.lumen_facets)

    def _press():
        f, dd = np.zeros(fast.ndofs), np.zeros(fast.pattern.keys.size)
        press.add_to(u, 0.6, f, dd)

    t_press, _ = best_of(_press, args.repeat)
    print(f"3-D assembly, paper design: {fast.ndofs} DOFs, {cm.mesh.t.shape[1]} tets, mixed u-p")
    print(row("NumPy (batched einsum) internal + tangent", f"{t_ref * 1e3:.0f} ms"))
    print(row("compiled (numba element loop) internal + tangent", f"{t_fast * 1e3:.0f} ms"))
    print(row("speed-up", f"{t_ref / t_fast:.1f}x"))
    print(row("follower pressure (lumen) for scale", f"{t_press * 1e3:.0f} ms"))
    print(row("max |f diff| / max |f|", f"{np.abs(f1 - f0).max() / np.abs(f0).max():.1e}"))
    print(row("max |K diff| / max |K|", f"{np.abs(d1 - d0).max() / np.abs(d0).max():.1e}"))


if __name__ == "__main__":
    main()
