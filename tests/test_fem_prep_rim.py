"""The rim master coupling (``fem_prep.rim_fit``, the coupling of ``fem_prep.couple_masters``): how the tooth roots load the rim.

References, independent of the code under test:

* a field affine in ``x`` is reproduced by any least-squares fit whose basis holds the constants
  (a partition of unity), at the fitted positions: linear algebra;
* the distributed nodal forces ``A N G^-1 F`` are, through the coupling's transformation ``T``,
  exactly the master forces ``F`` (virtual work), with the same resultant force and moment;
* a thin annular disc held at the bore under a uniform outward rim pressure ``p``: Lamé's plane
  stress solution ``u = A r + B / r`` with ``u(a) = 0`` and ``sigma_r(b) = p`` (Timoshenko &
  Goodier, Theory of Elasticity, Sec. 28); the masters, at the fitted radius ``R_hat``, move
  with the dilation as ``u(b) R_hat / b``.
"""

import dataclasses
import math
import pathlib
import tempfile

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from _examples import load_example
from _fem_prep_wheel import wheel_text
from test_fem_prep_physics import NU, E, _disc_text

import fem_prep
from fem_prep import (
    assemble_operators,
    couple_masters,
    mesh_body,
    parse_body,
    prepare,
    rim_fit,
    select_masters,
)
from jaxgear import io as jio
from jaxgear.dynamics import mesh_averaged_modes
from jaxgear.io import build_dynamic_model


@pytest.fixture(scope="module")
def wheel():
    body = parse_body(wheel_text(rim_coupling="distributing"))
    bm = mesh_body(body)
    ms = select_masters(bm, body)
    return body, bm, ms


def _axial_mass(z):
    """The 1-D Gram ``int N_j N_j' dz`` of the linear hats on the axial planes ``z`` (the
    linear element's mass matrix ``h / 6 [[2, 1], [1, 2]]``, assembled)."""
    out = np.zeros((len(z), len(z)))
    for i, h in enumerate(np.diff(z)):
        out[i : i + 2, i : i + 2] += h / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    return out


@pytest.mark.parametrize("which", ["test wheel", "accessory wheel"])
def test_station_gram_is_the_pitch_times_the_axial_mass_matrix(wheel, which):
    """The fit's Gram couples the masters of one station only, and each station's block is
    ``int N_k(theta) R dtheta x int N_j N_j' dz = R p M_1D`` (the quadratic faces integrate
    the hat times a quadratic in z exactly, up to the arc's curvature): positive definite,
    whatever the signs of the corner areas (the full consistent Gram ``N^T A N`` of the
    accessory wheel has negative eigenvalues: the spurious soft modes of the withdrawn fit)."""
    if which == "test wheel":
        _, bm, ms = wheel
    else:
        body = parse_body(fem_prep.embedded_body_text("accessory-wheel"))
        bm = mesh_body(body)
        ms = select_masters(bm, body)
    fit = rim_fit(bm, ms.rim_nodes, ms.rim_radius)
    Z, n_ax = ms.rim_nodes.shape
    G = fit.G.toarray().reshape(Z, n_ax, Z, n_ax)
    ref = ms.rim_radius * 2 * math.pi / Z * _axial_mass(bm.nodes[ms.rim_nodes[0], 2])
    for k in range(Z):
        assert np.abs(G[k, :, k] - ref).max() < 1e-4 * np.abs(ref).max()
        G[k, :, k] = 0.0
    assert not G.any()  # nothing between stations
    assert np.linalg.eigvalsh(ref)[0] > 0
    if which == "accessory wheel":
        full = (fit.N.T @ sp.diags(fit.areas) @ fit.N).toarray()
        assert np.linalg.eigvalsh(full)[0] < 0


def test_fit_reproduces_affine_fields_at_the_fitted_positions(wheel):
    body, bm, ms = wheel
    fit = rim_fit(bm, ms.rim_nodes, body.geometry.rim_outer_radius)
    rng = np.random.default_rng(0)
    a, B = rng.normal(size=3), rng.normal(size=(3, 3))
    u = a + bm.nodes[fit.nodes] @ B.T
    q = np.column_stack(
        [spla.spsolve(fit.G.tocsc(), fit.N.T @ (fit.areas * u[:, c])) for c in range(3)]
    )
    expect = a + fit.positions.reshape(-1, 3) @ B.T
    assert np.abs(q - expect).max() < 1e-10 * np.abs(expect).max()
    # consistent nodal areas: they sum to the face's area (of the quadratic geometry: the circle
    # is exact at the nodes only); serendipity corners negative, mid-sides positive
    g = body.geometry
    assert fit.areas.sum() == pytest.approx(2 * math.pi * g.rim_outer_radius * g.rim_width, 1e-3)
    corner = fit.nodes < bm.n_vertices
    assert np.all(fit.areas[corner] < 0) and np.all(fit.areas[~corner] > 0)
    # the masters sit on their axial planes and, radially, at the hat-weighted mean of the arc
    # over the two pitches: R 2 (1 - cos p) / p^2 (inside the arc by about R p^2 / 12)
    r_hat = np.hypot(fit.positions[..., 0], fit.positions[..., 1])
    R, p = g.rim_outer_radius, 2 * math.pi / ms.rim_nodes.shape[0]
    inside = R - r_hat
    assert inside == pytest.approx(R - R * 2 * (1 - math.cos(p)) / p**2, rel=0.01)
    assert np.allclose(fit.positions[..., 2], bm.nodes[ms.rim_nodes][..., 2], atol=1e-12)


def test_master_forces_are_a_distributed_traction_with_their_resultant(wheel):
    body, bm, ms = wheel
    ops = assemble_operators(bm.basis, body.material)
    cp = couple_masters(bm, ops, ms)
    fit = rim_fit(bm, ms.rim_nodes, body.geometry.rim_outer_radius)
    rng = np.random.default_rng(1)
    F = rng.normal(size=(fit.G.shape[0], 3))
    t = fit.N @ np.column_stack([spla.spsolve(fit.G.tocsc(), F[:, c]) for c in range(3)])
    f = np.zeros(bm.n_dofs)
    f.reshape(-1, 3)[fit.nodes] = fit.areas[:, None] * t
    # through T (the eliminated master nodes and the kept face nodes), exactly F on the masters
    fr = cp.T.T @ f
    expect = np.zeros(cp.T.shape[1])
    expect[cp.rim_dofs.ravel()] = F.ravel()
    assert np.abs(fr - expect).max() < 1e-10 * np.abs(F).max()
    # every face node carries a share: the load is spread, not put on the master nodes
    assert np.count_nonzero(np.abs(f) > 0) > 3 * fit.nodes.size * 0.9
    x = bm.nodes[fit.nodes]
    xh = fit.positions.reshape(-1, 3)
    fn = f.reshape(-1, 3)[fit.nodes]
    assert fn.sum(0) == pytest.approx(F.sum(0), abs=1e-10 * np.abs(F).sum())
    assert np.cross(x, fn).sum(0) == pytest.approx(
        np.cross(xh, F).sum(0), abs=1e-10 * np.abs(np.cross(xh, F)).sum()
    )


def _lame_outer(a, b, p):
    """u(b) of a plane-stress annulus with u(a) = 0 and sigma_r(b) = p."""
    A = p * (1 - NU**2) / E / ((1 + NU) + (1 - NU) * a**2 / b**2)
    return A * b - A * a**2 / b


def _disc_rim_error(rim, size, circ, a=20.0, b=100.0, h=2.0, Z=24, p=1e6):
    """Mean radial master displacement under a uniform rim pressure put on the masters
    (``F_c = p (2 pi b / Z) h e_r``), bearings held, over Lamé's ``u(b) R_hat / b``."""
    text = _disc_text(a, b, h, size, Z, circ, n_frequencies=1)
    text = text.replace("[condensation]", f'[condensation]\nrim_coupling = "{rim}"')
    prep = prepare(parse_body(text))
    K = prep.condensed.K
    x = prep.coupled.rim_positions.reshape(-1, 3)
    n_m = len(x)
    r_hat = np.hypot(x[:, 0], x[:, 1])
    er = x[:, :2] / r_hat[:, None]
    F = np.zeros(K.shape[0])
    F[: 3 * n_m].reshape(n_m, 3)[:, :2] = p * (2 * math.pi * b * 1e-3 / Z) * h * 1e-3 * er
    free = np.ones(K.shape[0], dtype=bool)
    free[3 * n_m : 3 * n_m + 6] = False  # the bearing node, held
    q = np.zeros(K.shape[0])
    q[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])
    ur = np.sum(q[: 3 * n_m].reshape(n_m, 3)[:, :2] * er, axis=1)
    ref = _lame_outer(a * 1e-3, b * 1e-3, p) * r_hat / (b * 1e-3)
    return float(np.mean(ur / ref) - 1)


MESHES = ((10.0, 24.0), (5.0, 12.0), (2.5, 6.0))  # element size, circumferential size (mm)


@pytest.mark.slow
def test_disc_under_rim_pressure_converges_to_lame_through_distributing_masters():
    """Nodal masters put the pressure on 24 corner nodes: the rim displacement grows without
    bound as the mesh is refined (+36 %, +58 %, +101 %). Distributing masters spread it over
    the face: -0.73, -0.65, -0.62 %, settled (steps of 0.08 and 0.03 %)."""
    nodal = [_disc_rim_error("nodal", *m) for m in MESHES]
    dist = [_disc_rim_error("distributing", *m) for m in MESHES]
    assert nodal[0] > 0.3 and nodal[2] > nodal[1] > nodal[0], nodal
    assert all(abs(e) < 0.01 for e in dist), dist
    assert abs(dist[2] - dist[1]) < 0.001 and abs(dist[1] - dist[0]) < 0.002, dist


def _wheel_station_compliance(rim, rim_mm, circ_mm):
    """Tangential and radial compliance (nm/N) of one station of the accessory wheel (a unit
    force over its axial masters by their face shares, bearings held), Guyan (exact statics)."""
    text = fem_prep.embedded_body_text("accessory-wheel")
    text = text.replace('method = "craig-bampton"', 'method = "guyan"')
    text = text.replace("[condensation]", f'[condensation]\nrim_coupling = "{rim}"')
    extra = "" if rim_mm is None else f"\nrim_size_mm = {rim_mm}"
    text = text.replace(
        "circumferential_size_mm = 4.6", f"circumferential_size_mm = {circ_mm}{extra}"
    )
    prep = prepare(parse_body(text))
    K = prep.condensed.K
    x = prep.coupled.rim_positions
    Z, n_ax, _ = x.shape
    dz = np.diff(x[0, :, 2])
    share = np.zeros(n_ax)
    share[:-1] += dz / 2
    share[1:] += dz / 2
    share /= share.sum()
    free = np.ones(K.shape[0], dtype=bool)
    free[3 * Z * n_ax : 3 * Z * n_ax + 12] = False  # the two bearing nodes, held
    er = np.append(x[0, 0, :2] / np.hypot(*x[0, 0, :2]), 0.0)
    et = np.array([-er[1], er[0], 0.0])
    out = []
    for e in (et, er):
        F = np.zeros(K.shape[0])
        F[: 3 * Z * n_ax].reshape(Z, n_ax, 3)[0] = share[:, None] * e
        q = np.zeros(K.shape[0])
        q[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])
        out.append(float(F @ q) * 1e9)
    return np.array(out)


@pytest.mark.slow
def test_accessory_wheel_station_compliance_with_distributing_masters():
    """The accessory wheel refined twice (rim section halved, then the circumference): with
    nodal masters one station's compliance keeps growing (tangential 6.66 -> 7.11 -> 7.53,
    radial 3.62 -> 3.95 -> 4.49 nm/N, +13 % and +24 % in all). Distributing masters (station
    Gram): 6.03 -> 6.07 -> 6.02 and 2.72 -> 2.77 -> 2.73 nm/N, the three within 2 %."""
    meshes = ((None, 4.6), (1.75, 4.6), (1.75, 2.3))
    nodal = np.array([_wheel_station_compliance("nodal", *m) for m in meshes])
    dist = np.array([_wheel_station_compliance("distributing", *m) for m in meshes])
    assert np.all(np.diff(nodal, axis=0) > 0.05 * nodal[:-1]), nodal  # > 5 % per refinement
    assert np.all(np.abs(dist / dist[0] - 1) < 0.025), dist
    assert np.all(np.abs(dist - dist[0]) < 0.5 * (nodal[2] - nodal[0])), (dist, nodal)


def _te_with_bodies(ex, case_name: str, texts) -> tuple[np.ndarray, np.ndarray]:
    """TE mean and RMS (µm) of the embedded case with its gear body replaced by each body-file
    text in turn (examples/rim_convergence.py's ``te_of``)."""
    case = jio.load_case(case_name)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, text in enumerate(texts):
            body = pathlib.Path(tmp) / f"gear-body-{k}.toml"
            body.write_text(text)
            rows.append(ex.te_of(case, str(body)))
    return np.array([r["te_mean_um"] for r in rows]), np.array([r["te_rms_um"] for r in rows])


@pytest.mark.slow
def test_accessory_spur_flexible_te_settles_under_body_refinement(fem_prep_cache):
    """TE of ``accessory-spur-flexible`` (80 N·m, 3000 rad/s) with the distributing wheel refined
    twice (examples/rim_convergence.py, docs/bench/rim_convergence.json): mean 43.36, 43.38, 43.38 µm,
    RMS 0.912, 0.909, 0.910 µm: 0.02 % and 0.2 % between the two finest (nodal masters: mean 44.00,
    44.40, 44.98, RMS 0.869, 0.846, 0.819 µm, 1.3 % and 3.1 %)."""
    ex = load_example("rim_convergence")
    texts = [ex.body_text("distributing", rim, circ) for _, rim, circ in ex.REFINEMENTS]
    mean, rms = _te_with_bodies(ex, "accessory-spur-flexible", texts)
    assert abs(mean[2] / mean[1] - 1) < 0.01 and abs(rms[2] / rms[1] - 1) < 0.01, (mean, rms)
    assert mean[1] == pytest.approx(43.38, rel=0.01) and rms[1] == pytest.approx(0.909, rel=0.02)


@pytest.mark.slow
def test_distributing_masters_leave_the_hybrid_modes_clean(fem_prep_cache, tmp_path):
    """The mesh-averaged modes of ``accessory-spur-flexible`` (80 N·m, at rest) with the wheel's
    rim masters nodal and distributing: the same modes below 7 kHz (measured 980/981, 1006/1007,
    1498/1502, 2137/2139, 3345/3350, 6137/6146, 6183/6294 Hz), none new. The withdrawn fit (the
    full consistent Gram, indefinite) added modes at 2.7 and 4.2 kHz carrying 40 and 55 % of
    their strain energy in the mesh."""
    case = jio.load_case("accessory-spur-flexible")
    body = tmp_path / "wheel-distributing.toml"
    body.write_text(
        fem_prep.embedded_body_text("accessory-wheel").replace(
            "[condensation]", '[condensation]\nrim_coupling = "distributing"'
        )
    )
    freqs = {}
    for name, gear_body in (("nodal", case.scene.gear_body), ("distributing", str(body))):
        spec = dataclasses.replace(case.scene, gear_body=gear_body)
        model, _ = build_dynamic_model(case, spec)
        modes = mesh_averaged_modes(model, positions_per_pitch=16)
        f = np.asarray(modes.omega)[~np.asarray(modes.rigid)] / (2 * np.pi)
        freqs[name] = f[f < 7000.0]
    nodal, dist = freqs["nodal"], freqs["distributing"]
    assert len(nodal) == len(dist) >= 6, (nodal, dist)
    np.testing.assert_allclose(dist, nodal, rtol=0.025)


@pytest.mark.slow
def test_power_helical_flexible_te_settles_under_body_refinement(fem_prep_cache):
    """TE of ``power-helical-flexible`` (310 N·m, 3000 rad/s) with the distributing power wheel
    refined twice (examples/rim_convergence.py power, docs/bench/rim_convergence_power.json): mean
    91.66, 92.29, 92.29 µm, RMS 0.365, 0.366, 0.366 µm, below 1 % between the two finest
    (measured 0.002 % and 0.03 %; about 35 minutes on 2 cores: the finest body has 333 000
    DOFs)."""
    ex = load_example("rim_convergence")
    texts = [ex.power_body_text(rim, circ) for _, rim, circ in ex.POWER_REFINEMENTS[1:]]
    mean, rms = _te_with_bodies(ex, "power-helical-flexible", texts)
    assert abs(mean[1] / mean[0] - 1) < 0.01 and abs(rms[1] / rms[0] - 1) < 0.01, (mean, rms)
    assert mean[1] == pytest.approx(92.29, rel=0.01) and rms[1] == pytest.approx(0.366, rel=0.02)
