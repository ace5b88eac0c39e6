"""The compiled element kernel's assembly equals the reference quadrature assembly.

The kernel (``softcath.fem.section_model.element_kernel``) integrates, projects the
volumetric part and condenses the bubbles triangle by triangle in compiled loops; the
peer is scikit-fem's quadrature assembly (``softcath.fem.section_model.element.assemble``)
on the same morphed mesh. The free-free block is then factorised by PARDISO or, where
MKL is missing, QDLDL: both must give the same section model.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import sparse

from softcath import design
from softcath.fem.adapter import geometry_from_design
from softcath.fem.section_model.batch import _kernel
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.laws import section_laws_from_design
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.template import morph, section_template
from softcath.studies.sweep.random_designs import random_designs

DESIGNS = random_designs(4, seed=61) + [design.resolve("paper")]


def _setup(d):
    g = geometry_from_design(d)
    template = section_template(g, mesh_size=MESH_SIZE, segments=SEGMENTS)
    mesh = morph(template, g)
    laws = section_laws_from_design(d, coil_modulus="tension")
    kernel = _kernel(template)
    labels = kernel.labels
    D = np.stack([laws[int(k)].D for k in labels])[None]
    lam = np.array([laws[int(k)].lam for k in labels])[None]
    ez = np.array([laws[int(k)].axial_modulus for k in labels])[None]
    return kernel, mesh, laws, D, lam, ez


def _rel(a, b) -> float:
    """Largest difference relative to the largest entry (0 when both are zero)."""
    a, b = np.asarray(a), np.asarray(b)
    scale = max(np.abs(a).max(), np.abs(b).max())
    return float(np.abs(a - b).max() / scale) if scale > 0 else 0.0


@pytest.mark.parametrize("d", DESIGNS, ids=lambda d: d.name)
def test_fast_assembly_equals_the_quadrature_assembly(d):
    kernel, mesh, laws, D, lam, ez = _setup(d)
    ops = kernel.assemble(kernel.geometry([mesh]), D, lam, ez)
    ref = assemble(mesh, laws)
    free = kernel.free
    n = free.size
    kff = sparse.csr_matrix((ops["data"][0], kernel.indices, kernel.indptr), shape=(n, n)).toarray()
    assert _rel(kff, ref.K_uu[free][:, free].toarray()) < 1e-10
    assert _rel(ops["K_ug"][0], ref.K_ug) < 1e-10
    assert _rel(ops["K_gg"][0], ref.K_gg) < 1e-10
    assert _rel(ops["f"][0], ref.f_lumen) < 1e-10
    assert ops["ybar"][0] == pytest.approx(ref.axial_centroid_y, rel=1e-10, abs=1e-12)
    assert _rel(ops["xr"][0], ref.bubble_from_retained) < 1e-10
    assert _rel(ops["xg"][0], ref.bubble_from_strains) < 1e-10


def test_both_factorisations_give_the_same_section_model(monkeypatch):
    """PARDISO (where MKL is installed) and the QDLDL fallback solve the same block alike."""
    from softcath.fem import pardiso
    from softcath.fem.section_model import batch

    if not pardiso.available():
        pytest.skip("MKL PARDISO is not installed: QDLDL is the only factorisation here")
    designs = DESIGNS[:2]
    batch._KERNELS.clear()
    with_pardiso = batch.section_models(designs)
    monkeypatch.setattr(pardiso, "available", lambda: False)
    batch._KERNELS.clear()
    with_qdldl = batch.section_models(designs)
    batch._KERNELS.clear()
    for a, b in zip(with_pardiso, with_qdldl, strict=True):
        assert a.result.backward_error < 1e-12 and b.result.backward_error < 1e-12
        for load in ("cap", "lumen"):
            ka, kb = a.result.curvature_per_mm_per_MPa[load], b.result.curvature_per_mm_per_MPa[load]
            assert ka == pytest.approx(kb, rel=1e-10)
            assert a.strain_range[load] == pytest.approx(b.strain_range[load], rel=1e-9)
        assert _rel(a.result.stiffness, b.result.stiffness) < 1e-10


def test_designs_of_one_template_are_assembled_together():
    """Batched over designs (m = 2): the second, with every modulus doubled, has twice the stiffness."""
    kernel, mesh, _, D, lam, ez = _setup(DESIGNS[0])
    one = kernel.assemble(kernel.geometry([mesh]), D, lam, ez)
    two = kernel.assemble(kernel.geometry([mesh, mesh]), np.concatenate([D, 2 * D]),
                          np.concatenate([lam, 2 * lam]), np.concatenate([ez, ez]))  # fmt: skip
    assert _rel(two["data"][0], one["data"][0]) < 1e-12
    assert _rel(two["data"][1], 2 * one["data"][0]) < 1e-12
    assert _rel(two["K_gg"][1], 2 * one["K_gg"][0]) < 1e-12
    assert _rel(two["xr"][1], one["xr"][0]) < 1e-10


def test_triangles_that_do_not_fit_the_mesh_are_refused():
    from softcath.fem.section_model.element_kernel import element_blocks

    kernel, mesh, _, D, lam, _ = _setup(DESIGNS[0])
    x6 = kernel.geometry([mesh])[0]
    sizes = {"dphi": kernel.dphi, "W": kernel.W, "Ng": kernel.Ng, "dNg": kernel.dNg, "nnz": kernel.nnz}
    scatters = {"slot_rr": kernel.slot_rr, "slot_rg": kernel.slot_rg, "n_ug": 3 * kernel.n}
    nel = kernel.nel
    bad = rf"x6: {nel - 1} triangles, must be a positive multiple of the mesh's {nel}"
    with pytest.raises(ValueError, match=bad):
        element_blocks(x6[:-1], D[0, :-1], lam[0, :-1], **sizes, **scatters)
    with pytest.raises(ValueError, match=rf"lam: shape \({nel - 1},\), must be \({nel},\)"):
        element_blocks(x6, D[0], lam[0, :-1], **sizes, **scatters)
