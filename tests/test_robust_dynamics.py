"""Dynamics over whole revolutions with manufacturing deviations (docs/robust.md,
"Dynamics with deviations"): the mesh table spans the deviations' period with one
time-constant reference; a single pitch deviation at low speed reproduces the quasi-static TE
step; a pinion runout gives mesh-order ± shaft-order sidebands in the dynamic TE (absent from the
rigid quasi-static TE), proportional to the runout; the window must keep the span."""

from __future__ import annotations

import math

import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import Newmark, SteadyState, dynamic_model, simulate
from jaxgear.scenes import TorsionalDynamics, disc_inertia


@pytest.fixture(scope="module")
def torsional():
    """The accessory spur pair (z1 = 45, z2 = 86) at 4 slices on solid-disc inertias."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=4)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    return case, mesh, TorsionalDynamics(mesh, i1, i2)


def _at_phase(theta, period, n):
    return np.round((np.mod(theta, period) - period / (2 * n)) / (period / n)).astype(int) % n


@pytest.mark.slow
def test_single_pitch_deviation_at_low_speed_gives_the_quasi_static_step(torsional):
    """Pinion tooth 3 ahead by f = 2 µm (f' = f cos α_t on the line of action); the run covers
    one pinion revolution (the span of pinion deviations: z1 periods) at 1/10 of the critical
    speed, 256 steps per mesh period. ΔTE = TE(deviation) − TE(perfect, same mesh phase): over
    the second half of the tooth's single-pair zone (where the quasi-static ΔTE is −f' exactly,
    docs/deviations.md) its mean is −f' within 1 %; more than one mesh period away from the
    tooth (the response settled) |ΔTE| < 2 % of f'."""
    case, mesh, scene = torsional
    p = case.pair
    z1 = p.pinion.teeth
    f, n = 2e-6, 3
    fpt = np.zeros(z1)
    fpt[n], fpt[n + 1] = f, -f
    dev = jg.GearDeviations(fpt, reference_pressure_angle=p.transverse_pressure_angle)
    mods = jg.Modifications(deviations=jg.Deviations(pinion=dev))
    model = dynamic_model(scene, mods, case.torque)
    perfect = dynamic_model(scene, None, case.torque)
    N = 256
    speed = float(model.critical_speeds()[-1]) / 10
    r1 = simulate(model, speed, integrator=Newmark(N), window=SteadyState(z1 + 5, z1))
    r0 = simulate(perfect, speed, integrator=Newmark(N), window=SteadyState(10, 2))
    th = np.asarray(r1.theta)
    assert th.size == z1 * N  # the kept window covers the revolution
    per = 2 * math.pi / z1
    te0 = np.empty(N)
    te0[_at_phase(np.asarray(r0.theta), per, N)[-N:]] = np.asarray(r0.transmission_error)[-N:]
    d_dyn = np.asarray(r1.transmission_error) - te0[_at_phase(th, per, N)]
    qs = [
        np.asarray(jg.quasi_static(mesh, m, case.torque, th).transmission_error)
        for m in (mods, None)
    ]
    d_qs = qs[0] - qs[1]
    fp = f * math.cos(p.transverse_pressure_angle)
    single = np.nonzero(np.isclose(d_qs, -fp, rtol=1e-6))[0]
    assert single.size > N // 4
    late = single[single.size // 2 :]
    assert d_dyn[late].mean() == pytest.approx(-fp, rel=0.01)
    touched = np.nonzero(np.abs(d_qs) > 1e-15)[0]
    after = (np.arange(th.size) - touched.max()) % th.size  # steps since the tooth left (cyclic)
    before = (touched.min() - np.arange(th.size)) % th.size
    far = (after > N) & (before > N) & (after < th.size - touched.size)
    assert np.abs(d_dyn[far]).max() < 0.02 * fp


def test_runout_gives_shaft_order_sidebands_in_the_dynamic_te(torsional):
    """A pinion runout F_r (eccentricity F_r/2) at 1/4 of the critical speed, one revolution
    kept at 64 steps per mesh period: the dynamic TE spectrum (jaxgear.te_spectrum) has the
    shaft-order line F_r/2 (to 0.1 %) and sidebands at z1 ± 1 and 2 z1 ± 1 above 1e-5 F_r/2,
    which the rigid quasi-static TE does not have (< 1e-9 F_r/2, docs/deviations.md); they are
    proportional to the runout (doubling F_r doubles them, to 1 %), and the mesh-order line does
    not depend on it."""
    case, mesh, _ = torsional
    # on the theoretical path: the shaft-order line F_r/2 is the runout's projection on the line
    # of action; at this speed the dynamic load reaches past the case's tip relief and corner
    # cells beyond the path (the case file's default) touch, which moves that line by 0.11 %
    p = case.pair
    scene = TorsionalDynamics(
        mesh.with_contact_geometry(jg.TheoreticalPath()),
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    )
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    N = 64
    orders = (1, z1 - 1, z1, z1 + 1, 2 * z1 - 1, 2 * z1 + 1)
    amps = {}
    for fr in (10e-6, 20e-6):
        dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(z1), runout=fr))
        model = dynamic_model(scene, jg.Modifications(deviations=dev), case.torque)
        speed = float(model.critical_speeds()[-1]) / 4
        r = simulate(model, speed, integrator=Newmark(N), window=SteadyState(z1 + 5, z1))
        spec = jg.te_spectrum(np.asarray(r.transmission_error), N, (z1, z2))
        o, a = np.asarray(spec.orders), np.asarray(spec.amplitude)
        amps[fr] = {q: a[np.argmin(np.abs(o - q))] for q in orders}
        assert amps[fr][1] == pytest.approx(fr / 2, rel=1e-3)
        for q in (z1 - 1, z1 + 1, 2 * z1 - 1, 2 * z1 + 1):
            assert amps[fr][q] > 1e-5 * fr / 2
    for q in (z1 - 1, z1 + 1, 2 * z1 - 1, 2 * z1 + 1):
        assert amps[20e-6][q] == pytest.approx(2 * amps[10e-6][q], rel=0.01)
    assert amps[20e-6][z1] == pytest.approx(amps[10e-6][z1], rel=1e-6)


def test_the_window_must_keep_the_deviation_span(torsional):
    case, _, scene = torsional
    z1 = case.pair.pinion.teeth
    dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(z1), runout=5e-6))
    model = dynamic_model(scene, jg.Modifications(deviations=dev), case.torque)
    with pytest.raises(ValueError, match="keep_periods = 4: the manufacturing deviations span 45"):
        simulate(model, 100.0, integrator=Newmark(16), window=SteadyState(50, 4))
    short = dynamic_model(scene, jg.Modifications(deviations=dev), case.torque, revolutions=2)
    assert jg.dynamics.span_periods(short) == 2 * z1
    with pytest.raises(ValueError, match="revolutions = 0"):
        dynamic_model(scene, jg.Modifications(deviations=dev), case.torque, revolutions=0)
