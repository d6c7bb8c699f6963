"""Load spectra of trains and planetary stages (ISO 6336-6:2019): the input's
bins carried to every mesh (jaxgear.rating.rate_train_spectrum, ``[rating.spectrum]`` of a train
or a stage file), each bin rated as the mesh's single-point rating is.

References: a one-bin spectrum at the case's operating point over the rating's life gives the
single-point rating's safety factors; a two-bin spectrum's damage sums are Miner's sum written
here on the same S–N line (ISO 6336-2's Z_NT corners as a piecewise power law), with each bin's
stress the single-point rating's at the bin's torque, carried to the mesh by hand (an idler
passes the input's force on: T_idler = T z_idler / z_input)."""

from __future__ import annotations

import copy
import itertools
import math
import tomllib
from importlib import resources

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli

TRAIN = tomllib.loads(
    resources.files("jaxgear.cases").joinpath("accessory-idler-train.toml").read_text()
)
TRAIN["material"].update(
    sigma_H_lim_MPa=1500.0, sigma_F_lim_MPa={"input": 430.0, "idler": 430.0, "output": 400.0}
)
TRAIN["operating"]["speed_rpm"] = 6000.0
TRAIN["rating"] = {
    "life_h": 20000.0,
    "viscosity_40C_mm2_s": 46.0,
    "roughness_Rz_flank_um": 3.0,
    "roughness_Rz_root_um": 10.0,
}
RPM = 2 * math.pi / 60
RATE = eqx.filter_jit(jr.rate)  # the single-point rating, compiled (as jaxgear run's)


def _train(spectrum):
    d = copy.deepcopy(TRAIN)
    d["rating"]["spectrum"] = spectrum
    return jio.parse_train(d)


def _k_a_1(settings):
    return eqx.tree_at(lambda s: s.application_factor, settings, 1.0)


def _cycles_to_failure(points, reference, stress):
    """N(σ) on the power law through ``points`` ((N, f), ...), σ = reference f, by hand;
    below the line's end no damage (N infinite)."""
    f = stress / reference
    if f < points[-1][1]:
        return math.inf
    for (n_a, f_a), (n_b, f_b) in itertools.pairwise(points):
        if f_b <= f <= f_a:
            k = math.log(f_a / f_b) / math.log(n_b / n_a)
            return n_a * (f_a / f) ** (1 / k)
    raise AssertionError(f"σ/σ_ref = {f} off the sloped part of the line")


def test_one_bin_train_spectrum_is_each_meshes_single_point_rating():
    case = _train({"torque_Nm": [80.0], "speed_rpm": 6000.0, "hours": [20000.0]})
    rcs = jio.ratings_of(case)
    meshes = [(rc.geometry, rc.operating, _k_a_1(rc.settings)) for rc in rcs]
    rated = jr.rate_train_spectrum(meshes, rcs[0].spectrum, jr.OperatingPoint(80.0, 6000 * RPM))
    for (geometry, op, settings), sr in zip(meshes, rated, strict=True):
        one = RATE(geometry, op, settings)
        assert np.allclose(sr.S_H, one.pitting.S_H, rtol=1e-9)
        assert np.allclose(sr.S_F, one.bending.S_F, rtol=1e-9)
        assert np.allclose(sr.cycles[0], one.pitting.cycles, rtol=1e-12)
    # the case file's spectrum is the input's carried to each mesh (idler: T z_idler/z_input)
    assert float(rcs[1].spectrum.torque[0]) == pytest.approx(80.0 * 61 / 45, rel=1e-12)
    assert float(rcs[1].spectrum.speed[0]) == pytest.approx(6000 * RPM * 45 / 61, rel=1e-12)


def test_two_bin_train_damage_is_miners_sum_by_hand(tmp_path):
    hours = [150.0, 2000.0]
    torques = [80.0 * 1.6, 80.0 * 1.3]
    case = _train({"torque_Nm": torques, "speed_rpm": 6000.0, "hours": hours})
    section = cli.rating_outputs(case, str(tmp_path))
    spectrum = section["spectrum"]
    rcs = jio.ratings_of(case)
    ratio = (1.0, 61 / 45)  # each mesh's driving torque over the input's
    for k, rc in enumerate(rcs):
        settings = _k_a_1(rc.settings)
        life = float(settings.life)
        treatments = settings.material.treatment.per_gear()
        for j in range(2):
            d_h = d_f = 0.0
            for t, h in zip(torques, hours, strict=True):
                one = RATE(rc.geometry, jr.OperatingPoint(t * ratio[k], rc.operating.speed),
                              settings)
                n = float(one.pitting.cycles[j]) * h * 3600.0 / life
                ref_h = float(one.pitting.sigma_HG[j] / one.pitting.Z_NT[j])
                ref_f = float(one.bending.sigma_FG[j] / one.bending.Y_NT[j])
                d_h += n / _cycles_to_failure(treatments[j].z_nt_points, ref_h,
                                              float(one.pitting.sigma_H[j]))
                d_f += n / _cycles_to_failure(treatments[j].y_nt_points, ref_f,
                                              float(one.bending.sigma_F[j]))
            assert d_h > 0 and d_f > 0
            assert spectrum["pitting"]["damage_sum"][k][j] == pytest.approx(d_h, rel=1e-8)
            assert spectrum["bending"]["damage_sum"][k][j] == pytest.approx(d_f, rel=1e-8)
    assert (tmp_path / "spectrum_idler_output.csv").exists()
    md = (tmp_path / "rating.md").read_text()
    assert md.count("Load spectrum and life") == 2
    lines = cli.train_rating_run_line(section)
    assert lines[-1].startswith("load spectrum (ISO 6336-6, 2 bins of the input")


def test_bad_train_spectrum_is_one_line():
    with pytest.raises(ValueError, match=r"rating.spectrum") as err:
        _train({"torque_Nm": [80.0, 60.0], "speed_rpm": 6000.0, "hours": [1.0]})
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match=r"rate_train_spectrum: reference"):
        jr.rate_train_spectrum([], jr.LoadSpectrum([1.0], 1.0, [1.0]), (80.0, 600.0))


def test_planetary_one_bin_spectrum_is_the_stage_rating_with_its_k_gamma(tmp_path):
    """nrel-5mw-planetary with a one-bin spectrum of its carrier torque and speed over the life
    and K_A = 1: each mesh's spectrum safety factors are its single-point rating's at the same
    K_γ (1.1 here, the run's load sharing in a full run)."""
    from jaxgear.cli.planetary import rating_section

    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    data["rating"].update(application_factor=1.0,
                          spectrum={"torque_Nm": [3.946e6], "speed_rpm": 1.2671 / RPM,
                                    "time_share": [1.0]})
    case = jio.parse_train(data)
    section = rating_section(case, str(tmp_path), 1.1)
    spectrum = section["spectrum"]
    assert np.allclose(spectrum["pitting"]["S_H"], section["pitting"]["S_H"], rtol=1e-9)
    assert np.allclose(spectrum["bending"]["S_F"], section["bending"]["S_F"], rtol=1e-9)
    assert (tmp_path / "spectrum_planet1_ring1.csv").exists()
