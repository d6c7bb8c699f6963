"""A transducer on the ring sees a nodal-diameter resonance that the Campbell list predicts: the
19/17/-53 test stage (three planets, ring held) on a flexible ring whose housing holds it
stiffly in the tangential and axial directions (so that the ND >= 2 flexural modes are the
lowest and isolated: the soft test housing's ND0/ND1 on the foundation no longer come first).
The planets' loads pass the ring's 53 teeth one by one; with three planets the ring's ND2 mode
is driven at the order 53 - 2 = 51 (the mesh order's lower sideband; jp.ring_resonances lists
it). The probe's order-51 line (the radial displacement of one tooth station, a transducer fixed
on the ring) grows between a speed below the crossing and the crossing by the single-mode
estimate of the coupled ring-and-stage mode, its damping ratio from the run's modal damping;
the ring made 10^3 stiffer shows no such growth.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _planetary_stage import SEQ, geometry, stage

import fem_prep as fp
import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.planetary as jp
from fem_prep.schema import parse_ring_body

jax.config.update("jax_enable_x64", True)

ZETA = 0.02
PLANAR = jp.PlanarPlanetary()
S = 24  # steps per mesh period (a multiple of the 3 planets)
ORDER = 51  # |z_r - n| for n = 2, the mesh order's lower sideband


@pytest.fixture(scope="module")
def ring_stations():
    """The embedded seq-test-ring's body (53 stations, a 9 mm rim) on a housing of 0.1 N/mm^3
    radially and 10 N/mm^3 tangentially and axially, condensed by fem_prep (a few seconds,
    then cached)."""
    text = fp.embedded_ring_text("seq-test-ring")
    head, tail = text.split("[support]")
    support = ('[support]\nkind = "elastic_foundation"\nradial_N_per_mm3 = 0.1\n'
               "tangential_N_per_mm3 = 10.0\naxial_N_per_mm3 = 10.0\n\n")
    body = parse_ring_body(head + support + "[mesh]" + tail.split("[mesh]")[1],
                           default_name="stiff-housed-test-ring", label="test ring")
    return fp.ring_stations(body)


def _coupled_mode(st, ring, F, M, x, model=None):
    """The coupled stage-and-ring mode that carries the ring's ND2 (written here): stiffness
    [[K_s, -V_r^T k E], [-E^T k V_r, F^-1 + E^T k E]] (the ring meshes' deflection V_r q - E u,
    E the station rows at the travel x), mass diag(M_s, M_u), damping diag(C_s, C_u) with
    C = M Phi diag(2 zeta omega) Phi^T M on the modes of each (the run's modal damping):
    (omega (rad/s), zeta) of the mode with the largest ring ND2 content."""
    model = model or PLANAR
    Ms, Ks = np.asarray(model.mass_matrix(st)), np.asarray(model.stiffness_matrix(st))
    _, Vr = (np.asarray(v) for v in model.mesh_deflection_rows(st))
    k = np.asarray(st.mesh_stiffnesses()[1])
    E = np.asarray(ring.station_rows(st, x))
    z2 = F.shape[0] * 2
    Ku, Mu = np.linalg.inv(F.reshape(z2, z2)), M.reshape(z2, z2)
    Ku, Mu = (Ku + Ku.T) / 2, (Mu + Mu.T) / 2
    n = Ks.shape[0]
    K = np.block([[Ks, -Vr.T @ (k[:, None] * E)], [-E.T @ (k[:, None] * Vr), Ku + E.T @ (k[:, None] * E)]])
    Mc = scipy.linalg.block_diag(Ms, Mu)

    def damping(m, kk):
        lam, phi = scipy.linalg.eigh(kk, m)
        mp = m @ phi
        return mp @ ((2 * ZETA * np.sqrt(np.clip(lam, 0, None)))[:, None] * mp.T)

    C = scipy.linalg.block_diag(damping(Ms, Ks), damping(Mu, Ku))
    # the damped modes (first-order form): the stage's stiff modes are heavily damped, which
    # moves the coupled mode (a perturbation phi^T C phi / 2 omega is not enough)
    m = K.shape[0]
    Minv = np.linalg.inv(Mc)
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-Minv @ K, -Minv @ C]])
    lam, vec = np.linalg.eig(A)
    theta = 2 * np.pi * np.arange(F.shape[0]) / F.shape[0]
    nd2 = np.concatenate([np.stack([np.cos(theta) * c, np.sin(theta) * c], -1).ravel()[None]
                          for c in (np.cos(2 * theta), np.sin(2 * theta))])
    disp = vec[:m]
    share = np.sum(np.abs(nd2 @ disp[n:]) ** 2, axis=0) / np.sum(np.abs(disp) ** 2, axis=0)
    share = np.where(lam.imag > 0, share, 0.0)
    j = int(np.argmax(share))
    w = abs(lam[j])
    return w, float(-lam[j].real / w)


def _probe_line(st, ring, geo, omega, periods=53 + 60, model=None):
    """The order-ORDER amplitude (m) of a probe on the ring (station 0's radial displacement)
    over the last carrier turn (53 mesh periods), constant meshes, 1000 N m."""
    run = jp.PlanetaryRun(1000.0, steps_per_period=S, periods=periods, keep_periods=53,
                          damping_ratio=ZETA)
    r = jp.planetary_dynamics(model or PLANAR, st,
                              jp.ConstantMeshes(base_pitch=geo.planet_ring.base_pitch), run,
                              jnp.asarray(omega), ring=ring)
    assert int(r.result) == 0
    z2 = 2 * ring.stations
    probe = np.asarray(r.displacement)[:, -z2]  # station 0 at angle 0: x is radial
    orders, amp = jp.order_spectrum(probe - probe.mean(), S * 53)
    assert orders[ORDER] == ORDER
    return amp[ORDER], amp


#: soft meshes (N/m): the planets barely stiffen the ring, so that the ring's own ND2 is the
#: resonance (with 5e8 N/m meshes the coupled mode sits 4.7 % above it in the planar model and
#: the response peaks another 2.5 % below that mode: the stage and the ring meet in different
#: frames, docs/planetary.md)
K_MESH = 1e6


def _growth(ring_stations, scale=1.0, w=None):
    """(coupled mode (omega, zeta), probe line at the mode's speed / at 0.8 of it) of the ring
    with its compliance times ``scale``, the planar model; at the speeds of ``w`` (rad/s) in
    place of the mode's if given."""
    F, M = np.asarray(ring_stations.compliance) * scale, np.asarray(ring_stations.mass)
    geo = geometry(**SEQ)
    st = stage(geo, 3, pin=3e8, sun_bearing=1e8, k_mesh=K_MESH)
    ring = jp.CondensedRing(F, M, modes=24)
    x = np.linspace(0.0, geo.planet_ring.base_pitch, 3, endpoint=False)
    modes = np.array([_coupled_mode(st, ring, F, M, xi) for xi in x])
    w_c, zeta_c = modes.mean(axis=0)
    speed = (w_c if w is None else w) / ORDER
    at, _ = _probe_line(st, ring, geo, speed)
    below, _ = _probe_line(st, ring, geo, RATIO * speed)
    return (w_c, zeta_c), at / below


RATIO = 0.8  # the speed below the crossing, as a fraction of it


def test_the_campbell_crossing_and_the_coupled_nd2_mode(ring_stations):
    """The fast part of the test below (no dynamics): on the stiffly housed ring ND2 is the
    lowest mode and isolated; the Campbell list puts it at order 51 (harmonic 1) and only
    there; the coupled stage-and-ring mode that carries ND2 lies within 1.5 % above the ring's
    own with the soft meshes, its damping ratio the run's (the ring's modal damping) within
    5 %; with stiff meshes (5e8 N/m) the planets stiffen it by more than 3 %."""
    nd = ring_stations.nd_frequencies
    assert nd[2] < 0.8 * min(f for n, f in nd.items() if n != 2)
    hits = [h for h in jp.ring_resonances(nd, 3, 53, 1) if h["nd"] == 2]
    assert [(h["harmonic"], h["order"]) for h in hits] == [(1, ORDER)]
    F, M = np.asarray(ring_stations.compliance), np.asarray(ring_stations.mass)
    geo = geometry(**SEQ)
    ring = jp.CondensedRing(F, M, modes=24)
    own = 2 * np.pi * nd[2]
    w, zeta = _coupled_mode(stage(geo, 3, pin=3e8, sun_bearing=1e8, k_mesh=K_MESH), ring, F, M,
                            0.0)
    assert 1.0 < w / own < 1.015 and zeta == pytest.approx(ZETA, rel=0.05)
    w_stiff, _ = _coupled_mode(stage(geo, 3, pin=3e8, sun_bearing=1e8), ring, F, M, 0.0)
    assert w_stiff / own > 1.03


@pytest.mark.slow
def test_ring_nd2_resonance_grows_the_probe_sideband_by_the_single_mode_estimate(
        ring_stations):
    """The Campbell list (jp.ring_resonances: three planets, 53 teeth, harmonic 1) puts ND2 at
    order 51; the coupled stage-and-ring mode that carries ND2 lies within 1.5 % of the ring's
    own (the list's crossing); the probe's order-51 line grows from 0.8 of the crossing speed to
    the crossing by the single-mode estimate |1 - r^2 + 2 i zeta r| / (2 zeta), zeta the coupled
    mode's damping ratio from the run's modal damping (within 10 %: the other modes' share; the
    Newmark period error is 0.5 %); the ring made 10^3 stiffer (ND2 far above) shows no
    growth."""
    nd = ring_stations.nd_frequencies
    assert nd[2] < 0.8 * min(f for n, f in nd.items() if n != 2)  # ND2 lowest, isolated
    hits = [h for h in jp.ring_resonances(nd, 3, 53, 1) if h["nd"] == 2]
    assert [(h["harmonic"], h["order"]) for h in hits] == [(1, ORDER)]
    (w_c, zeta_c), growth = _growth(ring_stations)
    campbell = 2 * np.pi * hits[0]["carrier_speed_hz"] * ORDER
    assert 1.0 < w_c / campbell < 1.015 and zeta_c == pytest.approx(ZETA, rel=0.05)
    estimate = abs(1 - RATIO**2 + 2j * zeta_c * RATIO) / (2 * zeta_c)
    print(f"w_c/campbell {w_c / campbell:.4f}, zeta_c {zeta_c:.4f}, growth {growth:.3f}, "
          f"estimate {estimate:.3f}")  # measured: 1.0105, 0.0198, 8.580, 9.134
    assert growth == pytest.approx(estimate, rel=0.1)
    (w_stiff, _), stiff = _growth(ring_stations, 1e-3, w_c)  # at the same two speeds
    assert w_stiff > 10 * w_c and stiff < 1.2
