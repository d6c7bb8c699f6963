"""Manufacturing deviations per tooth (docs/deviations.md): ISO 1328-1:2013
tolerances against the standard's formulas written out here, the stated statistics of the draws
for a grade, the quasi-static TE step of a single pitch deviation (single- and double-pair
contact), the TE and order spectrum of a runout, the case keys and the `jaxgear run` outputs."""

from __future__ import annotations

import fractions
import math
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli.run import run_case

# -- ISO 1328-1:2013 tolerances ------------------------------------------------------------------


def _round_by_hand(v):
    """5.2.3: > 10 µm to 1 µm, 5 to 10 µm to 0.5 µm, < 5 µm to 0.1 µm (halves up)."""
    if v > 10:
        return math.floor(v + 0.5)
    if v >= 5:
        return math.floor(2 * v + 0.5) / 2
    return math.floor(10 * v + 0.5) / 10


def _by_hand(m, d, b, a):
    """Formulas (5)-(12) of ISO 1328-1:2013 and F_rT = 0.9 F_pT, written out (mm in, µm out)."""
    q = 2 ** ((a - 5) / 2)
    fp = (0.001 * d + 0.4 * m + 5) * q
    Fp = (0.002 * d + 0.55 * d**0.5 + 0.7 * m + 12) * q
    fHa = (0.4 * m + 0.001 * d + 4) * q
    ffa = (0.55 * m + 5) * q
    fHb = (0.05 * d**0.5 + 0.35 * b**0.5 + 4) * q
    ffb = (0.07 * d**0.5 + 0.45 * b**0.5 + 4) * q
    raw = {
        "f_pT": fp,
        "F_pT": Fp,
        "f_HaT": fHa,
        "f_faT": ffa,
        "F_aT": (fHa**2 + ffa**2) ** 0.5,
        "f_HbT": fHb,
        "f_fbT": ffb,
        "F_bT": (fHb**2 + ffb**2) ** 0.5,
        "F_rT": 0.9 * Fp,
    }
    return {k: _round_by_hand(v) for k, v in raw.items()}


SIZES = [
    (1.5, 67.5, 11.5),
    (8.0, 400.0, 80.0),
]  # (m_n, d, b) in mm: the accessory pinion; a large gear


@pytest.mark.parametrize("grade", [4, 6, 8])
@pytest.mark.parametrize("size", SIZES)
def test_iso1328_tolerances_equal_the_formulas_by_hand(grade, size):
    m, d, b = size
    tol = jg.iso1328_tolerances(m * 1e-3, d * 1e-3, b * 1e-3, grade)
    assert tol.as_um() == pytest.approx(_by_hand(m, d, b, grade), abs=1e-9)


def test_iso1328_values_worked_by_hand():
    """Class 5 (step factor 1), m_n = 1.5 mm, d = 67.5 mm, b = 11.5 mm, worked on paper:
    f_pT = 0.0675 + 0.6 + 5 = 5.6675 → 5.5 µm; F_pT = 0.135 + 0.55·8.2158 + 1.05 + 12 = 17.70
    → 18 µm; f_HαT = 0.6 + 0.0675 + 4 = 4.6675 → 4.7 µm; f_fαT = 0.825 + 5 = 5.825 → 6.0 µm;
    F_αT = √(4.6675² + 5.825²) = 7.464 → 7.5 µm; f_HβT = 0.4108 + 1.1869 + 4 = 5.598 → 5.5 µm;
    f_fβT = 0.5751 + 1.5260 + 4 = 6.101 → 6.0 µm; F_βT = √(5.598² + 6.101²) = 8.280 → 8.5 µm;
    F_rT = 0.9 · 17.70 = 15.93 → 16 µm. Class 7: × 2."""
    t = jg.iso1328_tolerances(1.5e-3, 67.5e-3, 11.5e-3, 5).as_um()
    assert t == {
        "f_pT": 5.5,
        "F_pT": 18.0,
        "f_HaT": 4.7,
        "f_faT": 6.0,
        "F_aT": 7.5,
        "f_HbT": 5.5,
        "f_fbT": 6.0,
        "F_bT": 8.5,
        "F_rT": 16.0,
    }
    raw5 = jg.iso1328_tolerances(1.5e-3, 67.5e-3, 11.5e-3, 5, rounded=False)
    raw7 = jg.iso1328_tolerances(1.5e-3, 67.5e-3, 11.5e-3, 7, rounded=False)
    assert raw7.single_pitch == pytest.approx(2 * raw5.single_pitch, rel=1e-12)


@pytest.mark.parametrize(
    ("value", "rounded"),
    [
        (10.5, 11.0),
        (10.49, 10.0),
        (10.0, 10.0),
        (7.25, 7.5),
        (7.24, 7.0),
        (5.0, 5.0),
        (4.95, 5.0),
        (4.94, 4.9),
        (0.05, 0.1),
    ],
)
def test_iso1328_rounding_rules(value, rounded):
    assert jg.iso1328_round(value) == rounded


#: ISO 54 modules (mm) within ISO 1328-1's scope, for the scan of exact rounding ties
MODULES_MM = "0.5 0.6 0.8 1 1.25 1.5 2 2.5 3 4 5 6 8 10 12 16 20 25 32 40 50 60 70".split()


#: the common denominator of the scan's exact values (µm): m_n in 0.01 mm, the constants of
#: (5), (7), (8) in 0.001 µm per mm, and a step (√2)^(A−5) down to 1/4 (class 1)
DEN = 100 * 1000 * 4


def _half_up(n: int, below: bool = False) -> int:
    """5.2.3 on the exact value n / DEN µm (an integer numerator; ``below``: on a value just
    below it): > 10 to 1, 5 to 10 to 0.5, < 5 to 0.1, halves up; the rounded value's numerator
    over DEN (integer arithmetic: floor((v + q/2) / q) q with q = Q / DEN)."""
    if below:  # n − δ, 0 < δ << 1: the class of n unless n is a class's lower end
        Q = DEN if n > 10 * DEN else DEN // (2 if n > 5 * DEN else 10)
        return ((2 * n + Q) // (2 * Q) - ((2 * n + Q) % (2 * Q) == 0)) * Q
    Q = DEN if n > 10 * DEN else DEN // (2 if n >= 5 * DEN else 10)
    return (2 * n + Q) // (2 * Q) * Q


def _exact_num(m: int, z: int, grade: int) -> dict:
    """f_pT (5), f_HαT (7), f_fαT (8) as exact numerators over DEN (m_n in 0.01 mm, d = z m_n;
    an even A − 5, whose step (√2)^(A−5) = 2^k, k >= −2, is a power of 2): the values whose
    ties a scan can find."""
    k = (grade - 5) // 2
    four_step = 4 * 2**k  # 4 · 2^k, an integer for k >= −2
    d = z * m
    return {
        "f_pT": (d + 400 * m + 500_000) * four_step,
        "f_HaT": (400 * m + d + 400_000) * four_step,
        "f_faT": (550 * m + 500_000) * four_step,
    }


def test_iso1328_rounding_ties_round_half_up():
    """Exact ties of 5.2.3 round up in every class of an exact step (even A − 5): the audit's
    m_n 8 mm, z 97, class 1: f_fαT = 9.4 / 4 = 2.35 → 2.4 µm, and m_n 1 mm, z 100, class 3:
    f_pT = 5.5 / 2 = 2.75 → 2.8 µm; and every value of a scan of 23 modules × z 5-200 (spur,
    d = z m_n, passed in metres as floats) equals its exact rational value rounded half up
    (computed here in integers over a common denominator); 3 392 ties of f_pT, f_HαT, f_fαT,
    1 597 of them in classes 1 and 3, where the binary (√2)^(A−5), a bit below 1/4 or 1/2,
    rounded 1 588 down."""
    t = jg.iso1328_tolerances(8e-3, 97 * 8e-3, 20e-3, 1).as_um()
    assert t["f_faT"] == 2.4
    t = jg.iso1328_tolerances(1e-3, 100 * 1e-3, 20e-3, 3).as_um()
    assert t["f_pT"] == 2.8
    assert _half_up(235 * DEN // 100) == 24 * DEN // 10  # 2.35 -> 2.4 (a tie, up)
    assert _half_up(235 * DEN // 100, below=True) == 23 * DEN // 10
    ties = 0
    for grade in (1, 3, 5, 7, 9, 11):
        for text in MODULES_MM:
            m = fractions.Fraction(text)
            m100 = int(m * 100)
            assert m100 == m * 100
            for z in range(5, 201):
                if z * m < 5:
                    continue
                got = jg.iso1328_tolerances(float(m) * 1e-3, z * float(m) * 1e-3, 20e-3, grade)
                um = got.as_um()
                for key, exact in _exact_num(m100, z, grade).items():
                    rounded = _half_up(exact)
                    ties += rounded != _half_up(exact, below=True)  # the rounding jumps there
                    assert um[key] == rounded / DEN, (text, z, grade, key, exact)
    assert ties == 3392


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        ((1.5e-3, 67.5e-3, 11.5e-3, 12), "grade = 12 is out of range"),
        ((1.5e-3, 67.5e-3, 11.5e-3, 6.5), "grade = 6.5 is out of range"),
        ((0.3e-3, 67.5e-3, 11.5e-3, 6), "normal_module_mm = 0.3 mm is out of range"),
        ((1.5e-3, 67.5e-3, 2e-3, 6), "face_width_mm = 2 mm is out of range"),
    ],
)
def test_iso1328_refuses_extrapolation(args, needle):
    with pytest.raises(ValueError, match=needle):
        jg.iso1328_tolerances(*args)


# -- draws for a grade ---------------------------------------------------------------------------

TOL = jg.iso1328_tolerances(1.5e-3, 67.5e-3, 11.5e-3, 6)


def _draws(n_gears, teeth, seed=7):
    rng = np.random.default_rng(seed)
    return [jg.sample_gear_deviations(rng, teeth, TOL) for _ in range(n_gears)]


def test_draws_meet_the_tolerances_and_close():
    for g in _draws(200, 45):
        f = np.asarray(g.single_pitch)
        cum = np.asarray(g.cumulative_pitch)
        assert abs(f.sum()) < 1e-18
        assert np.abs(f).max() <= TOL.single_pitch * (1 + 1e-12)
        assert cum.max() - cum.min() <= TOL.cumulative_pitch * (1 + 1e-12)
        assert 0.0 <= float(g.runout) <= TOL.runout
        for slope, form, ts, tf, tt in (
            (
                g.profile_slope,
                g.profile_form,
                TOL.profile_slope,
                TOL.profile_form,
                TOL.profile_total,
            ),
            (g.helix_slope, g.helix_form, TOL.helix_slope, TOL.helix_form, TOL.helix_total),
        ):
            x = np.linspace(0, 1, 201)[:, None]
            trace = np.asarray(slope) * (x - 0.5) + np.asarray(form) * (2 * x - 1) ** 2
            assert np.all(np.ptp(trace, axis=0) <= tt * (1 + 1e-9))
            assert np.abs(slope).max() <= ts and np.abs(form).max() <= tf


@pytest.mark.parametrize(
    "n_gears",
    [
        1000,
        # default tier: tests/test_deviations.py::test_draws_have_the_stated_statistics[1000] (the same statistics of 1000 draws)
        pytest.param(3000, marks=pytest.mark.slow),
    ],
)
def test_draws_have_the_stated_statistics(n_gears):
    """Runout F_r ~ U(0, F_rT): mean F_rT/2, std F_rT/√12; phase ~ U(0, 2π); the per-tooth
    deviations symmetric about 0 (mean within 4 standard errors); single pitch deviations with
    the spread of U(−f_pT, f_pT) (std f_pT/√3 less the closure's √(1 − 1/z)) where the scaling
    to F_pT does not act (few teeth: 8). The 5 % on a standard deviation is 3.5 of its
    standard errors at 1000 draws (a uniform's: σ √(0.8 / 4n)), 6 at 3000."""
    gears = _draws(n_gears, 8)
    fr = np.array([float(g.runout) for g in gears])
    n = fr.size
    assert fr.mean() == pytest.approx(TOL.runout / 2, abs=4 * TOL.runout / math.sqrt(12 * n))
    assert fr.std() == pytest.approx(TOL.runout / math.sqrt(12), rel=0.05)
    ph = np.array([float(g.runout_phase) for g in gears])
    assert ph.min() >= 0 and ph.max() < 2 * math.pi
    assert ph.mean() == pytest.approx(math.pi, abs=4 * 2 * math.pi / math.sqrt(12 * n))
    for name in ("single_pitch", "profile_slope", "profile_form", "helix_slope", "helix_form"):
        v = np.concatenate([np.asarray(getattr(g, name)) for g in gears])
        assert abs(v.mean()) <= 4 * v.std() / math.sqrt(v.size), name
    f = np.concatenate([np.asarray(g.single_pitch) for g in gears])
    scaled = np.mean(
        [
            np.abs(np.asarray(g.single_pitch)).max() < 0.999 * TOL.single_pitch
            and np.ptp(np.asarray(g.cumulative_pitch)) > 0.999 * TOL.cumulative_pitch
            for g in gears
        ]
    )
    assert scaled < 0.02  # 8 teeth: the F_pT scaling (almost) never acts
    expected = TOL.single_pitch / math.sqrt(3) * math.sqrt(1 - 1 / 8)
    assert f.std() == pytest.approx(expected, rel=0.05)


def test_draws_are_reproducible_from_the_seed():
    a, b, c = _draws(1, 45, 3)[0], _draws(1, 45, 3)[0], _draws(1, 45, 4)[0]
    assert np.array_equal(np.asarray(a.single_pitch), np.asarray(b.single_pitch))
    assert not np.array_equal(np.asarray(a.single_pitch), np.asarray(c.single_pitch))


# -- the quasi-static TE -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def spur():
    """The rigid accessory spur pair, Weber stiffness at 4 slices, no modification (z1 = 45,
    z2 = 86, ε_α = 1.42)."""
    # theoretical path: the hand references sum each pair's path cells as loaded linear springs
    case = jio.load_case("accessory-spur").replace(contact_geometry=jg.TheoreticalPath())
    return case, case.mesh_model(slices=4)


def _te(mesh, torque, deviations, theta):
    mods = jg.Modifications(deviations=deviations)
    return np.asarray(jg.quasi_static(mesh, mods, torque, theta).transmission_error)


def _pair_stiffness(mesh, theta, pair):
    """K of tooth pair ``pair`` (Σ k l over its cells on the flanks) at each θ: line i = k − j."""

    def one(th):
        c = mesh.cells(th)
        k = jnp.round(
            (mesh.base_radius_pinion * th - jnp.mod(mesh.base_radius_pinion * th, mesh.base_pitch))
            / mesh.base_pitch
        )
        own = c.mask & (c.line == k - pair)
        return jnp.sum(jnp.where(own, c.stiffness * c.length, 0.0)), jnp.sum(
            jnp.where(c.mask & ~(c.line == k - pair), c.stiffness * c.length, 0.0)
        )

    kn, km = jax.jit(jax.vmap(one))(jnp.asarray(theta))  # one program (eager vmap: op by op)
    return np.asarray(kn), np.asarray(km)


@pytest.mark.parametrize("member", ["pinion", "gear"])
def test_single_pitch_deviation_gives_its_te_step(spur, member):
    """One tooth ahead by f (f_pt,n = +f, f_pt,n+1 = −f), on the reference circle: the line of
    action sees f cos α_t. In single-pair contact of that tooth the TE drops by exactly f cos α_t;
    where it shares the load with a perfect pair (both in contact: f cos α_t below the
    deflection) the drop is f cos α_t K_n/(K_n + K_m), its pair's share of the mesh stiffness
    (rigid mesh: F = K_n δ + K_m (δ − f'), TE = δ − f'); elsewhere nothing changes."""
    case, mesh = spur
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    z = z1 if member == "pinion" else z2
    f, n = 2e-6, 3
    fpt = np.zeros(z)
    fpt[n], fpt[n + 1] = f, -f
    g = jg.GearDeviations(fpt, reference_pressure_angle=case.pair.transverse_pressure_angle)
    dev = jg.Deviations(**{member: g})
    theta = jg.mesh_positions(mesh, 32, 8)  # pair 3 comes in during the 4th period
    d = _te(mesh, case.torque, dev, theta) - _te(mesh, case.torque, None, theta)
    fl = f * math.cos(case.pair.transverse_pressure_angle)
    kn, km = _pair_stiffness(mesh, theta, n)
    single = (kn > 0) & (km == 0)
    double = (kn > 0) & (km > 0)
    assert single.sum() >= 10 and double.sum() >= 20
    np.testing.assert_allclose(d[single], -fl, rtol=1e-9)
    np.testing.assert_allclose(d[double], -fl * kn[double] / (kn[double] + km[double]), rtol=1e-9)
    np.testing.assert_allclose(d[kn == 0], 0.0, atol=1e-15)
    share = kn[double] / (kn[double] + km[double])
    assert 0.3 < share.min() and share.max() < 0.7  # a real reduction, not a step of f


def test_runout_is_a_shaft_order_line_without_mesh_sidebands(spur):
    """An eccentricity e_r = F_r/2 turning with the pinion moves every pinion tooth in contact by
    the same e_r sin(θ + φ) along the line of action: δ0 = max e − e is unchanged, the TE is the
    perfect one less e_r sin(θ + φ), exactly. Over one revolution its spectrum has the line
    e_r at order 1 and nothing at the mesh orders ± 1 (the perfect TE is mesh-periodic): no
    sidebands to first order in the rigid quasi-static model (docs/deviations.md, "Runout")."""
    case, mesh = spur
    z1 = case.pair.pinion.teeth
    fr, phi = 6e-6, 0.4
    dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(z1), runout=fr, runout_phase=phi))
    ppp = 8
    theta = jg.mesh_positions(mesh, ppp, z1)
    te0 = _te(mesh, case.torque, None, theta)
    te = _te(mesh, case.torque, dev, theta)
    np.testing.assert_allclose(te - te0, -fr / 2 * np.sin(np.asarray(theta) + phi), atol=1e-15)
    spec = jg.te_spectrum(te, ppp, (z1, case.pair.gear.teeth))
    assert spec.revolutions == 1
    assert spec.at(1) == pytest.approx(fr / 2, rel=1e-9)
    for h in (1, 2):
        assert spec.at(h * z1) > 1e-7  # the mesh harmonics are there
        for side in (-1, 1):
            assert spec.at(h * z1 + side) < 1e-9 * fr


def test_gear_runout_line_at_the_gear_order_over_the_hunting_period(spur):
    """A gear runout over the hunting period (86 pinion revolutions for 45/86): the gear shaft
    order z1/z2 falls on a bin and reads e_r; the pinion order 1 reads 0."""
    case, mesh = spur
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    revs = jg.hunting_revolutions(z1, z2)
    assert revs == 86
    fr = 5e-6
    dev = jg.Deviations(gear=jg.GearDeviations(np.zeros(z2), runout=fr, runout_phase=1.0))
    ppp = 4
    theta = jg.mesh_positions(mesh, ppp, revs * z1)
    te = _te(mesh, case.torque, dev, theta)
    spec = jg.te_spectrum(te, ppp, (z1, z2))
    lines = {ln["label"]: ln for ln in spec.lines(1)}
    assert lines["gear shaft"]["bin_order"] == pytest.approx(z1 / z2, rel=1e-12)
    assert lines["gear shaft"]["amplitude_m"] == pytest.approx(fr / 2, rel=1e-6)
    assert lines["pinion shaft"]["amplitude_m"] < 1e-6 * fr


def test_zero_deviations_change_nothing_and_profile_slope_enters_per_tooth(spur):
    case, mesh = spur
    z1 = case.pair.pinion.teeth
    theta = jg.mesh_positions(mesh, 8, 3)
    zero = jg.Deviations(pinion=jg.GearDeviations(np.zeros(z1)))
    np.testing.assert_array_equal(
        _te(mesh, case.torque, zero, theta), _te(mesh, case.torque, None, theta)
    )
    # the same profile slope on every tooth is the modification's profile deviation
    slope = 3e-6
    dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(z1), profile_slope=slope))
    mod = jg.Modifications(
        pinion=jg.MemberModification(
            profile_deviation_roll=(0.0, 1.0), profile_deviation=(-slope / 2, slope / 2)
        )
    )
    ref = np.asarray(jg.quasi_static(mesh, mod, case.torque, theta).transmission_error)
    np.testing.assert_allclose(_te(mesh, case.torque, dev, theta), ref, atol=1e-15)


def test_deviation_arrays_must_match_the_teeth(spur):
    case, mesh = spur
    dev = jg.Deviations(pinion=jg.GearDeviations(np.zeros(44)))
    with pytest.raises(ValueError, match="deviations.pinion: 44 teeth is out of range"):
        jg.quasi_static(mesh, jg.Modifications(deviations=dev), case.torque)


def test_te_is_differentiable_in_the_pitch_deviations(spur):
    case, mesh = spur
    z1 = case.pair.pinion.teeth
    theta = jg.mesh_positions(mesh, 8, 6)

    def rms(f):
        dev = jg.Deviations(pinion=jg.GearDeviations(f))
        return jg.quasi_static(mesh, jg.Modifications(deviations=dev), case.torque, theta).te_rms

    f0 = jnp.asarray(np.random.default_rng(0).uniform(-2e-6, 2e-6, z1))
    # the gradient and the differences' values from one compiled program
    value_and_grad = jax.jit(jax.value_and_grad(rms))
    g = value_and_grad(f0)[1]
    h = 1e-9
    e = jnp.zeros(z1).at[4].set(h)
    fd = (float(value_and_grad(f0 + e)[0]) - float(value_and_grad(f0 - e)[0])) / (2 * h)
    assert float(g[4]) == pytest.approx(fd, rel=1e-4)


# -- case keys and jaxgear run -------------------------------------------------------------------


def _raw():
    raw = tomllib.loads(jio.embedded_case_text("accessory-spur"))
    raw.pop("scene", None)
    raw["mesh"].update(slices=2, positions_per_pitch=8)
    return raw


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"grade": 12}, "[deviations] grade = 12: out of range, allowed [1, 11]"),
        ({"grade": 6, "sigma": 1}, "[deviations] unknown key 'sigma'"),
        ({"seed": -1}, "[deviations] seed = -1: out of range, allowed >= 0"),
        ({"revolutions": "all"}, "[deviations] revolutions = 'all': allowed an integer >= 1"),
        ({"revolutions": 1.5}, "[deviations] revolutions = 1.5: must be an integer"),
        (
            {"pinion": {"pitch_um": [1.0, -1.0]}},
            "[deviations.pinion] pitch_um = [1, -1]: must be an array of 45 numbers",
        ),
        ({"pinion": {"pitch_um": [0.5] + [0.0] * 44}}, "sum to 0.5 µm, allowed a sum of 0"),
        (
            {"gear": {"runout_um": -2.0}},
            "[deviations.gear] runout_um = -2: out of range, allowed [0, 1500]",
        ),
        (
            {"gear": {"profile_slope_um": "big"}},
            "[deviations.gear] profile_slope_um = 'big': must be a number",
        ),
        ({"gear": {"lead_um": 1.0}}, "[deviations.gear] unknown key 'lead_um'"),
        ({"positions_per_pitch": 64, "revolutions": 1000}, "allowed <= 2000000"),
    ],
)
def test_bad_deviation_keys_give_one_line_errors(table, message):
    raw = _raw()
    raw["deviations"] = table
    with pytest.raises(jio.SchemaError) as err:
        jio.parse_case(raw)
    text = str(err.value)
    assert message in text and "\n" not in text


def test_given_values_replace_drawn_ones_and_run_writes_the_span(tmp_path):
    raw = _raw()
    pitch = [0.0] * 45
    pitch[2], pitch[3] = 1.5, -1.5
    raw["deviations"] = {
        "grade": 6,
        "seed": 2,
        "revolutions": 1,
        "positions_per_pitch": 4,
        "pinion": {"pitch_um": pitch, "runout_um": 4.0, "runout_phase_deg": 90.0},
    }
    case = jio.parse_case(raw)
    p, g = case.deviations.pinion, case.deviations.gear
    np.testing.assert_allclose(np.asarray(p.single_pitch) * 1e6, pitch, atol=1e-9)
    assert float(p.runout) == pytest.approx(4e-6) and float(p.runout_phase) == pytest.approx(
        math.pi / 2
    )
    assert float(np.abs(np.asarray(p.profile_slope)).max()) > 0  # still drawn for grade 6
    assert np.ptp(np.asarray(g.single_pitch)) > 0
    summary = run_case(case, str(tmp_path), harris_points=2, show_progress=False)
    dv = summary["deviations"]
    assert dv["grade"] == 6 and dv["revolutions_count"] == 1 and dv["positions"] == 45 * 4
    assert dv["values"]["pinion"]["single_pitch_um"] == pytest.approx(pitch, abs=1e-6)
    assert dv["values"]["pinion"]["runout_um"] == pytest.approx(4.0)
    assert (
        dv["tolerances_um"]["pinion"] == jg.iso1328_tolerances(1.5e-3, 67.5e-3, 11.5e-3, 6).as_um()
    )
    for name in ("te_span.csv", "spectrum.csv", "spectrum.json", "te_spectrum.png"):
        assert (tmp_path / "deviations" / name).stat().st_size > 0
    labels = [ln["label"] for ln in dv["spectrum_lines"]]
    assert {"pinion shaft", "gear shaft", "mesh", "mesh − pinion", "mesh + gear"} <= set(labels)


def test_grade_draw_is_reproducible_in_a_case():
    raw = _raw()
    raw["deviations"] = {"grade": 7, "seed": 5}
    a, b = jio.parse_case(raw), jio.parse_case(raw)
    np.testing.assert_array_equal(
        np.asarray(a.deviations.gear.helix_form), np.asarray(b.deviations.gear.helix_form)
    )
    assert a.deviation_settings["revolutions_count"] == 86


def test_sinusoidal_cumulative_pitch_gives_the_sidebands_of_the_load_share(spur):
    """A per-tooth cumulative pitch F_p,n = A sin(2π n/z1 + φ) (the spacing that eccentric
    cutting leaves) does give sidebands: while every pair in contact stays loaded the TE change
    is linear, ΔTE(θ) = −Σ_j w(θ − jT) F_p,j (w the load share K_j/K of one pair over its
    passage, T = 2π/z1), so its line at pinion order q = 1 + h z1 (and −1 + h z1) has the
    amplitude A |Ŵ(q)|, Ŵ(q) = (1/T) ∫ w(u) e^{−i q u} du, the Fourier coefficient of the
    share window (a window of one period, ε_α = 1, gives A |sinc(q/z1)|). The sum over the
    sampled window is computed here from the pair stiffnesses, independently of the solver."""
    case, mesh = spur
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    a, phi, ppp = 3e-6, 0.3, 16
    fp = a * np.sin(2 * np.pi * np.arange(z1) / z1 + phi)
    fpt = fp - np.roll(fp, 1)  # f_pt,n = F_p,n − F_p,n−1: closes
    g = jg.GearDeviations(fpt)
    np.testing.assert_allclose(np.asarray(g.cumulative_pitch), fp - fp[0], atol=1e-18)
    theta = jg.mesh_positions(mesh, ppp, z1)
    d = _te(mesh, case.torque, jg.Deviations(pinion=g), theta) - _te(mesh, case.torque, None, theta)
    spec = jg.te_spectrum(d, ppp, (z1, z2))
    window = np.asarray(theta[: 2 * ppp])  # pair 0 enters at θ = 0 and leaves before 2T
    kn, km = _pair_stiffness(mesh, window, 0)
    w = kn / (kn + km)
    for q in (1, z1 - 1, z1 + 1, 2 * z1 - 1, 2 * z1 + 1):
        hand = a * abs(np.sum(w * np.exp(-1j * q * window))) / ppp
        assert spec.at(q) == pytest.approx(hand, rel=1e-6), q
    sinc = abs(np.sinc((z1 + 1) / z1))
    assert 0.05 * a * sinc < spec.at(z1 + 1) < a * sinc  # the overlap (ε_α = 1.42) lowers them
