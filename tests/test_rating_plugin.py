"""A rating standard written outside jaxgear: one subclass of
``jaxgear.rating.AbstractRatingStandard`` in this file, given to a case in Python
(``case.replace(rating_standard=...)``) and run through ``jaxgear run``'s rating section
(:func:`jaxgear.cli.rating_outputs`: the ``summary.json`` section and ``rating.md``), its
stresses and safety factors checked against its formulas written out here by hand from the
case file's numbers; with a factor measured by jaxgear (``[rating] use_measured``) in place of
the standard's, as ISO 6336's editions take it."""

from __future__ import annotations

import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import pytest
from _rating_cases import rated_accessory_data
from jaxtyping import Array

import jaxgear as jg
import jaxgear.io as jio
from jaxgear import cli

Y_TOY = 2.5  # the toy standard's one tooth form factor
SOURCE = "toy standard, clause 1"


class ToyPitting(eqx.Module):
    sigma_H: Array
    S_H: Array


class ToyBending(eqx.Module):
    sigma_F: Array
    S_F: Array


class Toy(jg.rating.AbstractRatingStandard):
    """Hertz at the pitch point and a cantilever root, with K_A and the face load factors alone:
    σ_H = Z_E √(F_t K_A K_Hβ (u + 1)/(d₁ b u)), S_H = σ_Hlim/σ_H; σ_F = F_t/(b m_n) Y K_A K_Fβ,
    S_F = σ_Flim/σ_F (K_Fβ = K_Hβ)."""

    label: ClassVar[str] = "toy standard 1"
    form_factor: float = Y_TOY

    def load_factors(self, geometry, operating, settings):
        one = jnp.asarray(1.0)
        k_hb = settings.given.K_Hbeta
        k_hb = one if k_hb is None else jnp.asarray(k_hb)
        sources = dict.fromkeys(("K_v", "K_Halpha", "K_Falpha"), SOURCE) | {"K_A": "given"}
        sources |= dict.fromkeys(("K_Hbeta", "K_Fbeta"),
                                 SOURCE if settings.given.K_Hbeta is None else "given")
        k_a = jnp.asarray(settings.application_factor)
        return jg.rating.LoadFactors(k_a, one, k_hb, k_hb, one, one, {}, sources)

    def pitting(self, geometry, operating, settings, factors):
        g = geometry.derived()
        d1, b, u = g.reference_diameter[0], g.face_width, g.gear_ratio
        mat = settings.material
        z_e = jnp.sqrt(mat.youngs_modulus / (2 * jnp.pi * (1 - mat.poisson_ratio**2)))
        f_t = 2 * operating.torque / d1
        s = z_e * jnp.sqrt(f_t * factors.K_A * factors.K_Hbeta * (u + 1) / (d1 * b * u))
        return ToyPitting(s * jnp.ones(2), mat.sigma_h_lim / s)

    def bending(self, geometry, operating, settings, factors):
        g = geometry.derived()
        f_t = 2 * operating.torque / g.reference_diameter[0]
        s = f_t / (g.face_width * geometry.normal_module) * self.form_factor
        s = s * factors.K_A * factors.K_Fbeta
        return ToyBending(s * jnp.ones(2), settings.material.sigma_f_lim / s)


def _by_hand(k_hbeta: float) -> dict:
    """The toy's stresses of the accessory pair with its [rating] (tests/_rating_cases.py), from
    the case file's numbers: m_n 1.5 mm, z 45/86, spur, common face width 9.5 mm, 80 N·m, steel
    E 210 GPa, ν 0.3, σ_Hlim 1500 and σ_Flim 430 N/mm², K_A 1."""
    mn, z1, z2, b, torque = 1.5e-3, 45, 86, 9.5e-3, 80.0
    d1, u = z1 * mn, z2 / z1
    f_t = 2 * torque / d1
    z_e = math.sqrt(210e9 / (2 * math.pi * (1 - 0.3**2)))
    s_h = z_e * math.sqrt(f_t * k_hbeta * (u + 1) / (d1 * b * u))
    s_f = f_t / (b * mn) * Y_TOY * k_hbeta
    return {"sigma_H": s_h, "S_H": 1500e6 / s_h, "sigma_F": s_f, "S_F": 430e6 / s_f}


def _check(section: dict, k_hbeta: float) -> None:
    want = _by_hand(k_hbeta)
    p, b = section["pitting"], section["bending"]
    assert p["sigma_H_Pa"] == pytest.approx([want["sigma_H"]] * 2, rel=1e-12)
    assert p["S_H"] == pytest.approx([want["S_H"]] * 2, rel=1e-12)
    assert b["sigma_F_Pa"] == pytest.approx([want["sigma_F"]] * 2, rel=1e-12)
    assert b["S_F"] == pytest.approx([want["S_F"]] * 2, rel=1e-12)


def test_a_rating_standard_defined_in_a_test_runs_through_jaxgear_runs_rating_section(tmp_path):
    case = jio.parse_case(rated_accessory_data(slices=8, positions_per_pitch=8))
    assert case.pair.normal_module == 1.5e-3 and case.torque == 80.0  # the numbers of _by_hand
    toy = case.replace(rating_standard=Toy())
    section = cli.rating_outputs(toy, str(tmp_path))
    assert section["method"] == "toy standard 1"
    assert section["factors"]["K_Hbeta"] == {"value": 1.0, "source": SOURCE}
    _check(section, 1.0)
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "load capacity, toy standard 1" in table
    assert "| S_H | " in table and "S_Hmin = 1.000 | pass / pass |" in table
    # the case file's own standard is untouched: ISO 6336:2019, whose σ_H differs
    iso = cli.rating_outputs(case, str(tmp_path / "iso"))
    assert iso["method"] == "ISO 6336:2019 method B"


def test_the_toy_standard_rates_with_a_factor_jaxgear_measured(tmp_path):
    d = rated_accessory_data(slices=8, positions_per_pitch=8)
    d["rating"]["use_measured"] = ["K_Hbeta"]
    d["modifications"]["crowning"] = {"depth_um": 8.0}  # a measurable face load factor
    case = jio.parse_case(d).replace(rating_standard=Toy())
    result = jg.quasi_static(case.mesh_model(), case.modifications, case.torque,
                             positions_per_pitch=case.positions_per_pitch)
    section = cli.rating_outputs(case, str(tmp_path), result=result)
    measured = section["measured"]["K_Hbeta"]["value"]
    assert measured > 1.05  # the crowning loads the face's middle
    assert section["factors"]["K_Hbeta"]["value"] == pytest.approx(measured, rel=1e-12)
    assert section["factors"]["K_Hbeta"]["source"].startswith("measured")
    _check(section, measured)
