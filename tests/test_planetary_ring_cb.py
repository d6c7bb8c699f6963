"""The flexible ring's own dynamics inside its stations: the condensed FE ring reduced
Craig–Bampton style onto its Z stations and its fixed-interface modes
(fem_prep.ring_craig_bampton, jaxgear.planetary.CraigBamptonRing, [planetary.ring] dynamics =
"craig-bampton").

References: the condensed FE ring itself (prep.condensed: K_c, M_c, its own eigen-solution and
nodal diameters by fem_prep.ring_nd_frequencies) for the reduction and its convergence; the
station compliance F of fem_prep.ring_master_compliance (a Schur complement of the condensed
stiffness, another computation) for the statics; planetary_quasi_static with the station ring
(written on the N ring-mesh displacements, another formulation) for the zero-speed dynamics;
the rigid ring for the ring made 10^3 stiffer; the station ring with its Guyan mass at a
nodal-diameter crossing for what the interior modes change.
"""

import itertools
import json
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sla
from _planetary_stage import K0, RING_PIN_ERRORS, RING_TORQUE, SEQ, geometry, stage
from _planetary_stage import mesh_force_error as _error
from _planetary_stage import ring_run as _run
from _planetary_stage import seq_ring_case

import fem_prep as fp
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp

jax.config.update("jax_enable_x64", True)

RING = "seq-test-ring"  # 53 stations, 2 axial master planes, 4 FE modes: 216 fixed-interface
COUPLED = 57  # ... of which this many couple to the stations (the others: out of plane)


@pytest.fixture(scope="module")
def prep():
    return fp.prepare_ring(fp.load_ring_body(RING))


def station_map(prep) -> np.ndarray:
    """E (n_condensed, 2Z), written here from ring_master_compliance's definition: a station's
    in-plane (x, y) displacement is the trapezoid-weighted mean over its axial masters (masters
    first in the condensed coordinates, in the order of prep.master_dofs), zero on the modes."""
    teeth, nax, _ = prep.master_dofs.shape
    w = np.ones(nax) if nax == 1 else np.r_[0.5, np.ones(nax - 2), 0.5]
    E = np.zeros((prep.condensed.K.shape[0], 2 * teeth))
    for k in range(teeth):
        for a in range(nax):
            for d in range(2):
                E[(k * nax + a) * 3 + d, 2 * k + d] = w[a] / w.sum()
    return E


@pytest.fixture(scope="module")
def stations():
    """The embedded coarse test ring's stations (fem_prep cache): F, M_u, the fixed-interface
    modes' eigenvalues and coupling."""
    return fp.ring_stations(fp.load_ring_body(RING))


@pytest.fixture(scope="module")
def seq():
    return stage(geometry(**SEQ), 3, pin=3e8, sun_bearing=1e8)


def test_cb_basis_is_the_condensed_ring_on_its_stations(prep, stations):
    """T = [Phi, Psi] on the condensed ring: its station coordinates are the stations'
    displacements (E^T T = [I, 0], 1e-8: Phi = K_c^-1 E F^-1 and F^-1 of this soft-housed ring
    is ill-conditioned, measured 1.4e-9), T^T K_c T is the assembled K_cb = diag(F^-1, Lambda)
    (the static shapes and the fixed-interface modes statically uncoupled, the station block
    F^-1: 1e-10 of |K_cb|), T^T M_c T = M_cb with I on the modes (1e-12); each kept mode solves
    the constrained eigenproblem (its residual K_c psi - lambda M_c psi lies in the span of the
    station map E, 1e-9); the statics on the stations (K_cb^-1's station block) are
    ring_master_compliance's F (1e-10 of |F|, measured 3e-12); the cached RingStations (built
    in another process: the equal-frequency pairs of modes may come in another rotation, and
    BLAS's rounding differs) give the same K_cb (1e-10), station mass and M_ue M_ue^T
    (invariant to those rotations; 1e-8, both through Phi and F^-1 again: measured 3e-9) and
    lowest 30 frequencies (1e-9)."""
    c = prep.condensed
    K, M, T = fp.ring_craig_bampton(prep)
    F, _ = fp.ring_master_compliance(prep)
    z2 = 2 * F.shape[0]
    F = F.reshape(z2, z2)
    m = K.shape[0] - z2
    assert m == COUPLED and T.shape == (c.K.shape[0], z2 + m)
    E = station_map(prep)
    np.testing.assert_allclose(E.T @ T, np.eye(z2, z2 + m), rtol=0, atol=1e-8)
    np.testing.assert_allclose(T.T @ c.K @ T, K, rtol=0, atol=1e-10 * np.abs(K).max())
    np.testing.assert_allclose(K[:z2, :z2], np.linalg.inv(F), rtol=0,
                               atol=1e-10 * np.abs(K).max())
    np.testing.assert_allclose(T.T @ c.M @ T, M, rtol=0, atol=1e-12 * np.abs(M).max())
    np.testing.assert_allclose(M[z2:, z2:], np.eye(m), rtol=0, atol=1e-12)
    lam, psi = np.diag(K)[z2:], T[:, z2:]
    resid = c.K @ psi - c.M @ psi * lam
    along_e = E @ np.linalg.lstsq(E, resid, rcond=None)[0]
    assert np.abs(resid - along_e).max() < 1e-9 * np.abs(c.K @ psi).max()
    np.testing.assert_allclose(np.linalg.inv(K)[:z2, :z2], F, rtol=0,
                               atol=1e-10 * np.abs(F).max())
    Ks, Ms = stations.craig_bampton()
    np.testing.assert_allclose(Ks, K, rtol=0, atol=1e-10 * np.abs(K).max())
    np.testing.assert_allclose(Ms[:z2, :z2], M[:z2, :z2], rtol=0, atol=1e-8 * np.abs(M).max())
    cs, cm = Ms[:z2, z2:], M[:z2, z2:]
    np.testing.assert_allclose(cs @ cs.T, cm @ cm.T, rtol=0,
                               atol=1e-8 * np.abs(cm @ cm.T).max())
    lo = [0, 29]
    np.testing.assert_allclose(sla.eigh(Ks, Ms, subset_by_index=lo, eigvals_only=True),
                               sla.eigh(K, M, subset_by_index=lo, eigvals_only=True), rtol=1e-9)


def test_cb_nd_frequencies_converge_to_the_condensed_rings_own(prep):
    """The lowest frequency of each nodal diameter among the lowest 60 modes (ND 0..11) of the
    ring reduced on its stations (Guyan: T = Phi) and on the stations plus m = 7, 25, 57 (every
    coupled; each count ends a pair of equal-frequency modes) fixed-interface modes, against
    the condensed FE ring's own eigen-solution (ring_nd_frequencies): each ND's error never
    grows with m (Rayleigh–Ritz on nested bases, 1e-9 slack for rounding), the RMS error falls
    at each step, every coupled mode gives the condensed ring within 1e-8 (measured 3e-11 to
    2e-10), the Guyan station model's largest error is more than 10^3 times that (measured
    7.1e-5, at ND 9; RMS 4.4e-5, 4.4e-5, 1.6e-6, 1e-11)."""
    n_modes = 60
    ref = fp.ring_nd_frequencies(prep, n_modes)
    _, _, T = fp.ring_craig_bampton(prep)
    z2 = 2 * prep.master_dofs.shape[0]
    errors = []
    for m in (0, 7, 25, COUPLED):
        got = fp.ring_nd_frequencies(prep, n_modes, T[:, : z2 + m])
        assert set(got) >= set(ref)
        errors.append(np.array([got[n] / ref[n] - 1 for n in sorted(ref)]))
        print("m", m, "max", np.abs(errors[-1]).max(), "rms", np.sqrt(np.mean(errors[-1] ** 2)))
    assert sorted(ref) == list(range(12))
    for a, b in itertools.pairwise(errors):
        assert np.all(b <= a + 1e-9)
        assert np.sqrt(np.mean(b**2)) < np.sqrt(np.mean(a**2))
    assert np.all(errors[0] > -1e-9)  # the station model from above
    assert np.abs(errors[-1]).max() < 1e-8
    assert errors[0].max() > 1e3 * np.abs(errors[-1]).max()


def test_cb_ring_matrices_rows_and_modal_basis(stations, seq):
    """jaxgear.planetary.CraigBamptonRing from the cached stations: its (K, M) are fem_prep's K_cb, M_cb
    (RingStations.craig_bampton, numpy; 1e-12); the contact rows are the station ring's with
    zeros on the fixed-interface modes and the window's rows put on every coordinate equal them
    (1e-15); its modal basis at k = 8 and 2Z + m is mass-normalised and exact in statics (the
    kept modes' flexibility plus G is K^-1, whose station block is F: 1e-8 of |F|, as the
    station ring's modal basis)."""
    ring = jp.CraigBamptonRing.from_stations(stations)
    K, M, _ = (np.asarray(a) for a in ring.dynamic_matrices(jnp.float64, 0.05))
    Ks, Ms = stations.craig_bampton()
    np.testing.assert_allclose(K, Ks, rtol=0, atol=1e-12 * np.abs(K).max())
    np.testing.assert_allclose(M, Ms, rtol=0, atol=1e-12 * np.abs(M).max())
    z2, n = 2 * ring.stations, K.shape[0]
    assert n == z2 + COUPLED and ring.interior == COUPLED
    station = jp.CondensedRing(stations.compliance)
    for x in np.linspace(0.0, 0.05, 4):
        rows = np.asarray(ring.contact_rows(seq, x))
        np.testing.assert_allclose(rows[:, :z2], station.station_rows(seq, x), rtol=0, atol=0)
        assert not np.any(rows[:, z2:])
        idx, Ew = ring.window(seq, x)
        full = np.zeros((3, n))
        np.add.at(full.T, np.asarray(idx), np.asarray(Ew).T)
        np.testing.assert_allclose(full, rows, rtol=0, atol=1e-15)
    Fm = np.asarray(stations.compliance).reshape(z2, z2)
    for k in (8, n):
        r = jp.CraigBamptonRing.from_stations(stations, modes=k)
        Tk, _, G = (np.asarray(a) for a in r.modal_basis(jnp.float64))
        np.testing.assert_allclose(Tk.T @ M @ Tk, np.eye(k), atol=1e-9)
        lam = np.diag(Tk.T @ K @ Tk)
        flex = (Tk / lam) @ Tk.T + G
        np.testing.assert_allclose(flex[:z2, :z2], Fm, rtol=0, atol=1e-8 * np.abs(Fm).max())
    assert np.max(np.abs(G)) < 1e-9 * np.abs(Fm).max()


def _synthetic(z=16, m=3, modes=None, **kw):
    F = np.einsum("kl,ab->kalb", 3e-9 * np.eye(z), np.eye(2))
    Mu = np.einsum("kl,ab->kalb", 0.05 * np.eye(z), np.eye(2))
    args = dict(eigenvalues=np.full(m, 1e9), coupling=np.full((z, 2, m), 1e-3))
    args.update(kw)
    return jp.CraigBamptonRing(F, Mu, modes, **args)


@pytest.mark.parametrize("kw, words", [
    (dict(modes=36), "CraigBamptonRing: modes = 36 is out of range: allowed an integer 1..35 "
     "(2 x the 16 stations + 3 fixed-interface modes)"),
    (dict(modes=0), "CraigBamptonRing: modes = 0 is out of range"),
    (dict(eigenvalues=np.array([1e9, -1.0, 1e9])), "CraigBamptonRing: eigenvalues min = -1: "
     "allowed > 0"),
    (dict(coupling=np.zeros((16, 2, 2))), "CraigBamptonRing: eigenvalues (3,) and coupling "
     "(16, 2, 2): allowed (m,) and (16, 2, m)"),
    (dict(coupling=None), "CraigBamptonRing: mass, eigenvalues and coupling are required"),
])
def test_bad_cb_rings_are_one_line(kw, words):
    with pytest.raises(ValueError) as err:
        _synthetic(**kw)
    assert words in str(err.value) and "\n" not in str(err.value)
    assert _synthetic(modes=35).interior == 3


def test_bad_interior_count_is_one_line(stations):
    with pytest.raises(ValueError, match=r"interior = 58 is out of range: allowed an integer "
                       r"0\.\.57 \(the coupled fixed-interface modes\)"):
        jp.CraigBamptonRing.from_stations(stations, 58)
    with pytest.raises(ValueError, match=r"craig_bampton: modes = 58 is out of range"):
        stations.craig_bampton(58)


#: the run settings of the CB ring on all its coordinates (every coupled fixed-interface mode)
#: shared by the zero-speed, stiff-ring and ND-2 tests: one compiled Newmark for the three (the
#: speed and the ring's matrices are data; the ring's shape and these counts are static)
CB_RUN = dict(periods=2, steps=12, keep=1)


def test_zero_speed_cb_ring_is_the_station_rings_quasi_static_solution(seq, stations):
    """At 1e-6 rad/s over two mesh periods the CB ring (every coupled fixed-interface mode, on
    all its coordinates: the coordinate-space solve, as the station ring's zero-speed test)
    gives planetary_quasi_static's mesh forces and ring deflections with the station ring's
    compliance F at the same travels, to 1e-8: the fixed-interface modes add no static
    flexibility."""
    ring = jp.CraigBamptonRing.from_stations(stations)
    got = _run(seq, ring, omega=1e-6, **CB_RUN)
    static = jp.planetary_quasi_static(jp.PlanarPlanetary(), seq, jp.ConstantMeshes(),
                                       np.asarray(RING_TORQUE), got.travel, RING_PIN_ERRORS,
                                       ring=jp.CondensedRing(stations.compliance))
    np.testing.assert_allclose(got.sun_mesh_forces, static.sun_mesh_forces, rtol=1e-8)
    np.testing.assert_allclose(got.ring_mesh_forces, static.ring_mesh_forces, rtol=1e-8)
    w = np.asarray(static.ring_deflection)
    np.testing.assert_allclose(got.ring_deflection, w, rtol=0, atol=1e-8 * np.abs(w).max())
    assert got.displacement.shape[1] == len(jp.PlanarPlanetary().dof_names(seq)) + 106 + COUPLED


def _stiffer(st, factor, modes):
    """The condensed ring ``factor`` times stiffer (F / factor, Lambda x factor, same mass)."""
    return jp.CraigBamptonRing(np.asarray(st.compliance) / factor, st.mass, modes,
                               np.asarray(st.interior_eigenvalues) * factor, st.coupling)


# default tier: tests/test_planetary_ring_dynamics.py::test_stiff_fe_ring_equals_the_rigid_ring_constant_meshes (stiff flexible ring = rigid) and tests/test_planetary_ring_cb.py::test_zero_speed_cb_ring_is_the_station_rings_quasi_static_solution (the CB ring's run)
@pytest.mark.slow
def test_stiff_cb_ring_equals_the_rigid_ring(seq, stations):
    """The condensed ring made 10^3 stiffer (all its coupled fixed-interface modes, in 8 modes
    plus the static correction), constant meshes, 60 rad/s, a pin error: the rigid ring's mesh
    forces within 0.5 % (measured 0.14 %); the ring itself changes them by more (13 %)."""
    rigid = _run(seq, jp.RigidRing())
    stiff = _run(seq, _stiffer(stations, 1e3, 8))
    soft = _run(seq, _stiffer(stations, 1.0, 8))
    print("stiff", _error(stiff, rigid), "soft", _error(soft, rigid))
    assert _error(stiff, rigid) < 5e-3
    assert _error(soft, rigid) > 5e-3


def _nd2_crossing(stations) -> float:
    """The carrier speed (rad/s) at which the first mesh harmonic of the 3 planets meets the
    ring's 2-diameter mode (order 53 - 2 = 51; ring_resonances)."""
    hit = [r for r in jp.ring_resonances(stations.nd_frequencies, 3, 53, 1)
           if r["nd"] == 2 and r["harmonic"] == 1]
    assert hit and hit[0]["order"] == 51
    return 2 * math.pi * hit[0]["carrier_speed_hz"]


def test_cb_and_station_ring_at_the_nd2_crossing_constant_meshes(seq, stations):
    """The fast form of the next test: constant meshes at the 2-diameter crossing's carrier
    speed (90 rad/s): the CB ring (every coupled fixed-interface mode, all coordinates) and the
    station ring with its Guyan mass give mesh forces within 1e-3 (measured 6e-5: this coarse
    ring's station model is within 7e-5 of its own ND frequencies)."""
    omega = _nd2_crossing(stations)
    station = _run(seq, jp.CondensedRing(stations.compliance, stations.mass), omega=omega,
                   **CB_RUN)
    cb = _run(seq, jp.CraigBamptonRing.from_stations(stations), omega=omega, **CB_RUN)
    print("CB vs station", _error(cb, station))
    assert _error(cb, station) < 1e-3


@pytest.mark.slow
def test_cb_and_station_ring_at_the_nd2_crossing_real_contact(seq, stations):
    """Real contact (19/17/-53, uniform k0), 12 periods at the 2-diameter crossing's carrier
    speed (the first mesh harmonic meets the ring's ND-2 mode): the dynamic factor of each mesh
    with the CB ring (every coupled fixed-interface mode) and with the station ring (Guyan
    mass), both on all their coordinates, within 0.5 % (measured 1.2e-4; mesh forces 8.8e-4 of
    the largest; the ND-2 frequencies differ by 7e-7)."""
    omega = _nd2_crossing(stations)
    meshes = jp.ContactMeshes.from_geometry(geometry(**SEQ), seq.planet_angles, jg.Uniform(K0))
    station = _run(seq, jp.CondensedRing(stations.compliance, stations.mass), meshes, omega,
                   periods=12)
    cb = _run(seq, jp.CraigBamptonRing.from_stations(stations), meshes, omega, periods=12)
    for a, b in zip(station.dynamic_factors, cb.dynamic_factors, strict=True):
        print("DF station", np.asarray(a), "CB", np.asarray(b))
        np.testing.assert_allclose(b, a, rtol=5e-3)
    print("mesh forces CB vs station", _error(cb, station))


def _nrel2(**ring):
    import tomllib

    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-stage2"))
    data["planetary"]["ring"].update(ring)
    return data


NREL2_RING = "nrel-5mw-stage2-ring"


def test_cb_keys_map_to_the_cb_ring():
    """dynamics = "craig-bampton": modes (the fixed-interface modes, default every coupled one)
    and integration_modes (default 24) in the spec, its summary and words."""
    spec = jio.parse_train(_nrel2(model="condensed", body=NREL2_RING,
                                  dynamics="craig-bampton", modes=12)).form.spec.ring_model
    assert (spec.dynamics, spec.modes, spec.integration_modes) == ("craig-bampton", 12, 24)
    assert spec.summary() == {"model": "condensed", "body": NREL2_RING,
                              "dynamics": "craig-bampton", "modes": 12, "integration_modes": 24}
    assert "Craig-Bampton, 12 fixed-interface modes, 24 modes integrated" in spec.words()
    spec = jio.parse_train(_nrel2(model="condensed", body=NREL2_RING, dynamics="craig-bampton",
                                  integration_modes=40)).form.spec.ring_model
    assert (spec.modes, spec.integration_modes) == (None, 40)
    assert "all coupled fixed-interface modes" in spec.words()


@pytest.mark.parametrize("ring, words", [
    (dict(dynamics="mass", integration_modes=8), "[planetary.ring] integration_modes = 8: "
     "allowed only with dynamics = \"craig-bampton\""),
    (dict(dynamics="modal", integration_modes=8), "[planetary.ring] integration_modes = 8: "
     "allowed only with dynamics = \"craig-bampton\""),
    (dict(dynamics="mass", modes=8), "[planetary.ring] modes = 8: allowed only with dynamics = "
     "\"modal\" or \"craig-bampton\""),
    (dict(dynamics="craig-bampton", modes=379), "[planetary.ring] modes = 379: out of range, "
     "allowed [1, 378] (the fixed-interface DOFs of ring body 'nrel-5mw-stage2-ring': its 93 "
     "stations' axial masters and 6 modes)"),
    (dict(dynamics="craig-bampton", modes=10, integration_modes=197), "[planetary.ring] "
     "integration_modes = 197: out of range, allowed [1, 196]"),
])
def test_bad_cb_keys_are_one_line(ring, words):
    with pytest.raises(jio.SchemaError) as err:
        jio.parse_train(_nrel2(model="condensed", body=NREL2_RING, **ring))
    msg = str(err.value)
    assert words in msg and "\n" not in msg


def test_more_modes_than_the_ring_couples_is_one_line(stations):
    """modes within the body's fixed-interface DOFs (216) but beyond the 57 that couple, or
    splitting a pair of equal-frequency modes: refused in one line when the sweep builds the
    ring (the count needs the condensed ring)."""

    data = seq_ring_case()
    data["planetary"]["ring"].update(dynamics="craig-bampton", modes=100)
    spec = jio.parse_train(data).form.spec.ring_model
    with pytest.raises(jio.SchemaError) as err:
        spec.dynamic_ring()
    msg = str(err.value)
    assert ("[planetary.ring] modes = 100: out of range, allowed [1, 57] (the fixed-interface "
            "modes that ring body 'seq-test-ring' couples to its stations)") in msg
    assert "\n" not in msg
    data["planetary"]["ring"].update(modes=8)
    with pytest.raises(jio.SchemaError, match=r"\[planetary.ring\] modes = 8: splits a pair of "
                       r"equal-frequency fixed-interface modes \(a nodal-diameter pair; allowed 7 "
                       r"or 9\)"):
        jio.parse_train(data).form.spec.ring_model.dynamic_ring()
    data["planetary"]["ring"].update(modes=57)
    ring = jio.parse_train(data).form.spec.ring_model.dynamic_ring()
    assert isinstance(ring, jp.CraigBamptonRing) and ring.interior == 57 and ring.modes == 24


# a first-look step: the sweep warns that it under-resolves the top mode (tests/test_planetary_step_resolution.py)
@pytest.mark.filterwarnings("ignore:.*time step under-resolved")
@pytest.mark.slow
def test_sweep_with_a_cb_ring_end_to_end(tmp_path):
    """jaxgear sweep on the small stage of tests/test_planetary_ring_case.py with its coarse
    ring as a Craig–Bampton ring (every coupled fixed-interface mode, 24 modes integrated), two
    speeds: sweep.json names the ring model; its dynamic factors are the modal station ring's
    (24 of its 106 modes) within 1 % (the same ring, another basis; measured 5e-6, the sun
    meshes' 1.12 at 10 rad/s and 1.25 at 20; while the corners took the stage's rolling it
    read 53 and the two rings differed by 10 %: docs/extended-contact.md, "The pair's
    rolling")."""
    from _toml import case_toml

    from jaxgear.cli import main

    out = {}
    for name in ("craig-bampton", "modal"):
        data = seq_ring_case()
        data["planetary"]["ring"].update(dynamics=name)
        path = tmp_path / f"{name}.toml"
        path.write_text(case_toml(data))
        assert main(["sweep", str(path), "--speeds", "10:20:2", "--out",
                     str(tmp_path / name), "--quiet"]) == 0
        out[name] = json.loads((tmp_path / name / "sweep.json").read_text())
    s = out["craig-bampton"]
    assert s["ring"] == {"model": "condensed", "body": RING, "dynamics": "craig-bampton",
                         "integration_modes": 24}
    assert "Craig-Bampton" in s["ring_model"]
    diff = np.abs(np.asarray(s["dynamic_factor_mesh"]) / out["modal"]["dynamic_factor_mesh"] - 1)
    print("DF CB vs modal station ring", diff.max())
    assert diff.max() < 1e-2
