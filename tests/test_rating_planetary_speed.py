"""The planetary rating's measured K_v (jaxgear.cli.planetary.measured_k_v): the dynamic
factor of `jaxgear run`'s planetary speed sweep at the operating input speed, interpolated
linearly as a pair's (jaxgear.cli.measured_dynamic_factor), each planet's mesh over its static
share of the mean path load, the largest over the planets; reported per rated mesh beside ISO's
K_v and rated with in its place only where `[rating] use_measured` names it."""

import numpy as np
import pytest

import jaxgear.io as jio
from test_rating_planetary_measured import iso_and_measured, rated_case

# the contact model a stub measured row states (jaxgear.rating.contact_model's words)
CONTACT = "stub contact model"

#: a three-planet sweep as sweep.json writes it: 4 input speeds, per speed the 3 sun/planet
#: meshes then the 3 ring/planet meshes (values chosen so that the largest planet differs
#: between the speeds and between the kinds)
SPEEDS = [100.0, 200.0, 300.0, 400.0]
DF = [
    [1.02, 1.03, 1.01, 1.04, 1.02, 1.03],
    [1.10, 1.20, 1.15, 1.08, 1.30, 1.12],
    [1.40, 1.25, 1.35, 1.22, 1.18, 1.45],
    [1.05, 1.06, 1.07, 1.09, 1.08, 1.02],
]
SWEEP = {
    "model": "planar lumped model",
    "ring_model": "rigid ring",
    "speeds_rad_s": SPEEDS,
    "mesh_names": [f"sun-planet {k}" for k in (1, 2, 3)] + [f"ring-planet {k}" for k in (1, 2, 3)],
    "dynamic_factor_mesh": DF,
}
EQUAL = {"planar": {"sun_mesh_forces_N": [5e4] * 3, "ring_mesh_forces_N": [5e4] * 3,
                    "k_gamma": 1.0}}


def _by_hand(speed, j, share=1.0):
    """Mesh j's dynamic factor at ``speed`` written out: the straight line between the two
    swept speeds around it, over the planet's static share."""
    i = int(np.searchsorted(SPEEDS, speed)) - 1
    t = (speed - SPEEDS[i]) / (SPEEDS[i + 1] - SPEEDS[i])
    return (DF[i][j] + t * (DF[i + 1][j] - DF[i][j])) / share


def test_k_v_is_the_largest_planets_interpolated_dynamic_factor():
    """Equal sharing: each kind's K_v is the largest of its 3 planets' dynamic factors, each the
    straight line between the neighbouring swept speeds (1e-12); outside the swept speeds
    nothing (None), as a pair's."""
    from jaxgear.cli.planetary import measured_k_v

    for speed in (237.5, 180.0, 300.0, 100.0):
        k = measured_k_v(SWEEP, speed, EQUAL, CONTACT)
        sun = max(_by_hand(speed, j) for j in range(3))
        ring = max(_by_hand(speed, j) for j in range(3, 6))
        assert k[0]["value"] == pytest.approx(sun, abs=1e-12)
        assert k[1]["value"] == pytest.approx(ring, abs=1e-12)
        assert "planar lumped model" in k[0]["source"] and "3 planets" in k[0]["source"]
    assert measured_k_v(SWEEP, 99.0, EQUAL, CONTACT) is None and measured_k_v(SWEEP, 401.0, EQUAL, CONTACT) is None
    assert measured_k_v(None, 200.0, EQUAL, CONTACT) is None


def test_unequal_sharing_divides_each_planet_by_its_static_share():
    """With pin errors the planets' static loads differ (F_j = s_j × mean): the sweep's dynamic
    factor (over the mean path load) of planet j is divided by s_j, so K_v is the mesh's
    dynamic load over its own static one and K_γ K_v does not count s_j twice. The load-sharing
    model taken is the rating's K_γ's (the 3D one where present)."""
    from jaxgear.cli.planetary import measured_k_v

    f = np.array([1.12, 0.95, 0.93]) * 4e4
    share = f / f.mean()
    sharing = {"planar": EQUAL["planar"],
               "spatial": {"sun_mesh_forces_N": f.tolist(), "ring_mesh_forces_N": (-f).tolist(),
                           "k_gamma": float(share.max())}}
    k = measured_k_v(SWEEP, 237.5, sharing, CONTACT)
    for kind in (0, 1):
        want = max(_by_hand(237.5, 3 * kind + j, share[j]) for j in range(3))
        assert k[kind]["value"] == pytest.approx(want, abs=1e-12)
    assert "spatial load sharing" in k[0]["source"]


def test_planet_dynamic_factors_on_arrays_against_the_hand_interpolation():
    """:func:`jaxgear.rating.planet_dynamic_factors` on the arrays themselves (no sweep.json):
    the (s, 2N) columns split into the N sun/planet then the N planet/ring meshes, each kind
    the largest planet's straight line at the speed over its static share (1e-12); None for
    both kinds outside the swept speeds; a last axis of odd length refused in one line."""
    from jaxgear.rating import planet_dynamic_factors

    f = np.array([1.12, 0.95, 0.93]) * 4e4
    share = f / f.mean()
    sun, ring = planet_dynamic_factors(np.array(SPEEDS), np.array(DF), 237.5, f, -f[::-1])
    assert sun == pytest.approx(max(_by_hand(237.5, j, share[j]) for j in range(3)), abs=1e-12)
    assert ring == pytest.approx(max(_by_hand(237.5, 3 + j, share[::-1][j]) for j in range(3)),
                                 abs=1e-12)
    assert planet_dynamic_factors(np.array(SPEEDS), np.array(DF), 401.0, f, f) == (None, None)
    with pytest.raises(ValueError, match=r"dynamic_factors has shape \(4, 5\)"):
        planet_dynamic_factors(np.array(SPEEDS), np.array(DF)[:, :5], 237.5, f, f)


def test_the_rating_takes_the_3d_models_sharing_where_there():
    """:func:`jaxgear.planetary.rating_sharing_model`: the 3D model's where the load sharing has
    it, else the planar one's; neither refused in one line."""
    from jaxgear.planetary import rating_sharing_model

    assert rating_sharing_model({"planar": 0, "torsional": 0}) == "planar"
    assert rating_sharing_model({"planar": 0, "torsional": 0, "spatial": 0}) == "spatial"
    assert rating_sharing_model(["spatial"]) == "spatial"
    with pytest.raises(ValueError, match="models = \\['torsional'\\]"):
        rating_sharing_model({"torsional": 0})


def test_use_measured_k_v_rates_each_mesh_with_the_sweeps(tmp_path):
    """Reported beside ISO's (not used) by default; `use_measured = ["K_v"]` (the other load
    factors given, so that only K_v moves): σ_F ∝ K_v and σ_H ∝ √K_v against the ISO rating
    (σ_F = σ_F0 K_A K_γ K_v K_Fβ K_Fα, σ_H ∝ √(K_A K_γ K_v K_Hβ K_Hα); 1e-10), the source and
    rating.md's row saying it was used. Without a sweep: a one-line warning naming K_v."""
    from jaxgear.cli.planetary import rating_section

    k_v = [{"value": 1.31, "source": "stub", "contact_model": CONTACT},
           {"value": 1.17, "source": "stub", "contact_model": CONTACT}]
    given = 'K_Hbeta = 1.15\nK_Fbeta = 1.12\nK_Halpha = 1.0\nK_Falpha = 1.0\n'  # within ISO's limits
    plain = rating_section(rated_case(tmp_path, given), str(tmp_path), 1.1, k_v=k_v)
    assert plain["measured"]["K_v"]["value"] == [1.31, 1.17]
    assert (tmp_path / "rating.md").read_text().count("| K_v measured | ") == 2
    case = rated_case(tmp_path, given + 'use_measured = ["K_v"]\n')
    iso, sec, md = iso_and_measured(case, tmp_path, "K_v", k_v=k_v)
    ratio = np.array([1.31, 1.17]) / np.asarray(iso["factors"]["K_v"]["value"])
    assert sec["factors"]["K_v"]["value"] == pytest.approx([1.31, 1.17], abs=1e-12)
    np.testing.assert_allclose(np.asarray(sec["bending"]["sigma_F_Pa"]),
                               np.asarray(iso["bending"]["sigma_F_Pa"]) * ratio[:, None],
                               rtol=1e-10)
    np.testing.assert_allclose(np.asarray(sec["pitting"]["sigma_H_Pa"]),
                               np.asarray(iso["pitting"]["sigma_H_Pa"])
                               * np.sqrt(ratio)[:, None], rtol=1e-10)
    assert sec["K_gamma"] == iso["K_gamma"]
    assert md.count("| K_v measured | ") == 2 and "| yes: [rating] use_measured |" in md


def test_the_run_hands_its_sweep_to_the_rating(tmp_path, monkeypatch):
    """`jaxgear run` on a planetary case sweeps first and hands the sweep to the stage's files
    (whose rating takes its K_v from it); the stages replaced by stand-ins."""
    import jaxgear.cli.planetary_sweep as cli_planetary

    case = jio.load_case("lin-parker-1999")
    sweep = dict.fromkeys(["model", "speed_of", "speeds_rad_s", "dynamic_factor",
                           "max_dynamic_factor", "speed_of_max_rad_s", "mesh_names",
                           "max_dynamic_factor_mesh", "k_gamma", "max_k_gamma",
                           "k_gamma_mean_load", "max_k_gamma_mean_load",
                           "ring_model", "ring", "steps_per_period",
                           "steps_resolution", "excitation"])
    seen = []
    monkeypatch.setattr(cli_planetary, "planetary_sweep", lambda *a, **kw: sweep)
    monkeypatch.setattr(cli_planetary, "planetary_files",
                        lambda *a: seen.append(a) or {"case": case.name})

    class Args:
        quiet = True

    cli_planetary.planetary_run_files(case.form, case, str(tmp_path), Args(), True)
    assert seen[0][-1] is sweep


# a first-look step: the sweep warns that it under-resolves the top mode (tests/test_planetary_step_resolution.py)
@pytest.mark.filterwarnings("ignore:.*time step under-resolved")
@pytest.mark.slow
def test_embedded_stage_k_v_is_the_sweep_at_the_operating_speed(tmp_path):
    """nrel-5mw-planetary, swept by the planetary dynamic model at `jaxgear run`'s speeds around
    the operating one (0.914, 1 and 1.057 of it: the run's sweep includes the operating speed):
    each kind's K_v is the largest planet's dynamic factor (over its static share) at the
    operating speed (1e-12); interpolated between its neighbours alone (the 8-speed grid) it
    lies within the planets' factors there, at most the larger of the two speeds' largest (a
    maximum of straight lines is convex)."""
    from jaxgear.cli.planetary import measured_k_v, sharing_models, sharing_summary
    from jaxgear.cli.planetary_sweep import run_speeds, sweep_summary

    case = jio.load_case("nrel-5mw-planetary")
    spec = case.form.spec
    stage = spec.stage(case)
    s = run_speeds(case)
    i = int(np.argmin(np.abs(s - case.speed)))
    assert s[i] == pytest.approx(case.speed, rel=1e-12) and s.size == 9
    sw, _ = sweep_summary(case.form, case, s[i - 1:i + 2])
    sharing = sharing_summary(spec, stage, spec.torques(case.torque),
                              sharing_models(spec, stage))
    df = np.asarray(sw["dynamic_factor_mesh"])  # (3, 2N)
    apart = sw | {"speeds_rad_s": [s[i - 1], s[i + 1]], "dynamic_factor_mesh": df[[0, 2]],
                  "mesh_frequency_Hz": [sw["mesh_frequency_Hz"][k] for k in (0, 2)]}
    k, k_apart = (measured_k_v(w, case.speed, sharing, CONTACT) for w in (sw, apart))
    name = [m for m in ("planar", "spatial") if m in sharing][-1]
    n = spec.n_planets
    for kind, key in enumerate(("sun_mesh_forces_N", "ring_mesh_forces_N")):
        f = np.abs(np.asarray(sharing[name][key]))
        d = df[:, kind * n:(kind + 1) * n] / (f / f.mean())
        assert k[kind]["value"] == pytest.approx(d[1].max(), abs=1e-12)
        ends = d[[0, 2]]
        assert ends.min() <= k_apart[kind]["value"] <= ends.max(axis=1).max() + 1e-12
