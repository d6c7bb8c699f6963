"""Mortar patch test (seed II-21/22; docs/hybrid.md, "Mortar patch test"): contact cells on a
non-matching face.

The construction lives in ``examples/mortar_patch.py`` (loaded here, it also draws
``docs/bench/mortar_patch.png``): a 2-D plane-strain block in scikit-fem (x = the face width, y =
depth, lateral rollers u_x = 0, u_y = 0 at the bottom, E = 210 GPa, ν = 0.3; width 20 mm, depth
10 mm, 2 elements in depth) is pressed by N_DE equal cells, each carrying f·Δ. The top-face
nodes are the masters; with A the interface weights, the load is Aᵀ(f Δ) and the cell
displacement q = A u_top. Interfaces: collocation (the face at the cell centre), mortar (2.26)
(``jaxgear.scenes.mortar_weights()`` on the face at the cell ends and centre), split (Simpson on
each piece between element ends: a reference). The face is linear between corner nodes, as
jaxgear's rim faces along the axis: the weights are the axial part of
``FlexibleMember.face_weights`` of a member whose axial master planes are the element ends.

Exact solution: a laterally confined layer, σ_yy = −f, ε_xx = ε_zz = 0, so
u_y = −f y / M with M = λ + 2μ = E (1 − ν) / ((1 + ν)(1 − 2ν)) (checked on the FE field).

Elements:

* ``Q4``: linear faces, jaxgear's consistent case. The FE space holds the exact solution, so
  the error only measures how far Aᵀ(f Δ) is from the consistent load ∫ N_i f. With nested
  cells both Simpson and the midpoint rule integrate the linear N_i exactly: mortar *and*
  collocation are exact (to solver precision). A cell straddling an element end sees a kink;
  the Simpson rule on |x − t| over [−1, 1] errs by −(3|t| − 1)(|t| − 1)/3, which vanishes at
  |t| = 1/3: in the 3×8 layout both element ends (x = 1/3, 2/3 of the face) sit exactly there,
  so the mortar is exact in 3×8 too — a coincidence of that layout, not a property. 4×7 shows
  the straddling error.
* ``Q8`` with the interface on the corner nodes only (the linear face, as fem_prep's hex20 rim
  faces condensed on their corners): a uniform f gives point loads on the corners, not the
  consistent 1/6, 2/3, 1/6 split: with nested cells all three interfaces coincide and the cells
  move uniformly (the rollers make the pattern periodic) but *not* by q_exact (the local
  compliance of the corner loads; 39 % on this coarse block — measured, not asserted).
* ``Q8-quadratic``: the face quadratic on its three edge nodes — the reference case.
  The seed gives neither the block's proportions nor the depth mesh; depth = width / 2 with
  2 elements in depth reproduces all of its table to the printed digits (asserted below);
  e.g. depth = width with 4 elements in depth gives about half its errors.
"""

import json
from pathlib import Path

import jax
import numpy as np
import pytest
from _examples import load_example
from skfem.models.elasticity import lame_parameters

from jaxgear.scenes import mortar_weights

jax.config.update("jax_enable_x64", True)

ROOT = Path(__file__).resolve().parents[1]
EXACT = 1e-10  # solver precision (relative)


@pytest.fixture(scope="module")
def mp():
    mod = load_example("mortar_patch")
    return mod


@pytest.fixture(scope="module")
def table(mp):
    return mp.table()


def test_exact_solution_is_the_confined_layer(mp):
    lam, mu = lame_parameters(mp.E, mp.NU)
    f, h = mp.LOAD, mp.DEPTH
    assert mp.exact_displacement() == pytest.approx(-f * h / (lam + 2.0 * mu), rel=1e-14)
    # consistent loads (split) reproduce the exact field everywhere, for both element kinds
    for element in ("Q4", "Q8-quadratic"):
        q, u, locs = mp.fe_solve(4, 7, element, "split")
        ux, uy, y = u[0::2], u[1::2], locs[1, 1::2]
        scale = abs(mp.exact_displacement())
        np.testing.assert_allclose(ux / scale, 0.0, atol=EXACT)
        np.testing.assert_allclose(uy / scale, -f * y / (lam + 2.0 * mu) / scale, atol=EXACT)
        np.testing.assert_allclose(q, 1.0, atol=EXACT)


def test_interface_weights_are_jaxgears():
    assert np.allclose(np.array(mortar_weights()) * 30.0, [5.0, 20.0, 5.0])


def test_linear_face_is_the_hat_interpolation(mp):
    x_nodes = np.linspace(0.0, mp.WIDTH, 5)
    pts = np.linspace(0.0, mp.WIDTH, 23)
    A = mp.linear_face(x_nodes, pts)
    hats = np.stack([np.interp(pts, x_nodes, np.eye(5)[i]) for i in range(5)], axis=1)
    np.testing.assert_allclose(A, hats, atol=1e-14)
    for kind in mp.INTERFACES:  # partition of unity: a uniform field is read exactly
        np.testing.assert_allclose(mp.interface(x_nodes, 7, kind).sum(axis=1), 1.0, atol=1e-14)


def test_simpson_on_a_kink_and_the_3x8_coincidence():
    m1, m2, m3 = mortar_weights()
    for t in np.linspace(-0.95, 0.95, 39):
        simpson = 2.0 * (m1 * abs(-1.0 - t) + m2 * abs(t) + m3 * abs(1.0 - t))
        exact = 1.0 + t * t  # ∫_{-1}^{1} |x - t| dx
        assert simpson - exact == pytest.approx(-(3 * abs(t) - 1) * (abs(t) - 1) / 3, abs=1e-14)
    # 3 elements x 8 cells: the element ends 8/3 and 16/3 cell widths sit at t = ±1/3
    for end in (8.0 / 3.0, 16.0 / 3.0):
        t = 2.0 * (end - (np.floor(end) + 0.5))
        assert abs(t) == pytest.approx(1.0 / 3.0, abs=1e-14)


def test_q4_nested_cells_are_exact(table):
    for kind in ("collocation", "mortar", "split"):
        assert table["Q4"]["4x8"][kind] < EXACT, kind


def test_q4_straddling_cells(table):
    err = table["Q4"]["4x7"]
    assert err["collocation"] > 1e-2  # spikes
    assert 1e-3 < err["mortar"] < err["collocation"]  # (2.26) is not exact across element ends
    assert err["split"] < EXACT
    err = table["Q4"]["3x8"]
    assert err["collocation"] > 1e-2
    assert err["mortar"] < EXACT  # the |t| = 1/3 coincidence (docstring)
    assert err["split"] < EXACT


def test_q4_straddling_spike_sits_at_the_straddled_element_end(mp):
    q = mp.solve(4, 7, "Q4", "collocation")
    assert np.argmax(np.abs(q - 1.0)) == 3  # the centre cell straddles x = width / 2
    np.testing.assert_allclose(q, q[::-1], atol=EXACT)  # the layout is symmetric


def test_q8_corner_only_interface_is_uniform_but_offset(mp, table):
    qs = [mp.solve(4, 8, "Q8", kind) for kind in mp.INTERFACES]
    for q in qs:
        np.testing.assert_allclose(q, qs[0], atol=EXACT)  # nested: the three coincide
        np.testing.assert_allclose(q, q[0], atol=EXACT)  # uniform (periodic corner loads)
    assert abs(qs[0][0] - 1.0) > 1e-2  # ... but the corner point loads are not consistent
    assert table["Q8"]["4x7"]["collocation"] > table["Q8"]["4x7"]["mortar"]


@pytest.mark.parametrize(
    ("layout", "collocation", "mortar"),
    [("4x7", 10.7, 3.7), ("3x8", 1.3, 0.16), ("4x8", 0.6, 0.0)],
)
def test_q8_quadratic_reproduces_hybrid_md_table(table, layout, collocation, mortar):
    err = table["Q8-quadratic"][layout]
    half_digit = {10.7: 0.05, 3.7: 0.05, 1.3: 0.05, 0.16: 0.005, 0.6: 0.05}
    assert abs(100 * err["collocation"] - collocation) <= half_digit[collocation]
    if mortar == 0.0:
        assert err["mortar"] < EXACT  # nested
    else:
        assert abs(100 * err["mortar"] - mortar) <= half_digit[mortar]
    assert err["split"] < EXACT


def test_docs_table_is_current(table):
    path = (
        ROOT / "docs" / "bench" / "mortar_patch.json"
    )  # committed; regenerate: python examples/mortar_patch.py
    docs = json.loads(path.read_text(encoding="utf-8"))["errors"]
    for el, rows in table.items():
        for layout, errs in rows.items():
            for kind, value in errs.items():
                assert docs[el][layout][kind] == pytest.approx(value, abs=1e-9)
