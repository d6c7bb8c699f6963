"""Life of the NREL 5 MW gearbox's parallel stage (the embedded ``nrel-5mw-stage3``) under a
wind turbine's load spectrum, by ISO 6336-6 (:func:`jaxgear.rating.rate_spectrum`), beside the
single-point rating at rated power that the case carries. At the spectrum's own loads no bin
reaches the stage's S–N lines (no damage: the stage is rated with S_H 1.8 at rated power and K_A
1.25); the safety factors under the spectrum say how far the loads could rise before the 20
years are used up, and the figure shows which bins would use them up (the damage at the loads
scaled by S, where the sum is 1).

The spectrum is an ESTIMATE written for this example, not a published one: the hub-height wind
of an IEC class I site (a Rayleigh distribution, Weibull shape 2, mean 10 m/s) in 1 m/s bins from
cut-in (3 m/s) to cut-out (25 m/s), over the case's 20 years (175 200 h); in each bin the rotor's
power P = 5 MW (v³ − 3³)/(11.4³ − 3³) below rated wind (11.4 m/s) and 5 MW above, and its speed
12.1 rpm × v/11.4 within [6.9, 12.1] rpm (the NREL 5 MW turbine's cut-in, rated and cut-out
winds and its rotor speed range; a cubic power curve between them); the stage's pinion turns
96.354 times faster than the rotor and carries T = P/ω. The time below cut-in and above cut-out
is one standstill bin (no load cycles). K_A = 1 in the spectrum (ISO 6336-6: the spectrum holds
the machines' loads); the case's single-point rating keeps its K_A 1.25.

Writes load_spectrum_wind.png and load_spectrum_wind.json into docs/bench/ (or the folder
given). Run from the repository root: ``python examples/load_spectrum_wind.py [out_dir]`` (about
half a minute).
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
RATED_POWER = 5e6  # W
CUT_IN, RATED_WIND, CUT_OUT = 3.0, 11.4, 25.0  # m/s
ROTOR_RPM = (6.9, 12.1)  # the rotor's speed range (1/min)
RATIO = 96.354  # the stage's pinion speed over the rotor's
MEAN_WIND, SHAPE = 10.0, 2.0  # IEC class I hub-height mean wind, Rayleigh


def weibull_cdf(v):
    """The share of time with a wind below ``v`` (m/s)."""
    scale = MEAN_WIND / math.gamma(1 + 1 / SHAPE)
    return 1.0 - np.exp(-((np.asarray(v) / scale) ** SHAPE))


def wind_spectrum(life_s: float) -> tuple[jr.LoadSpectrum, np.ndarray]:
    """The pinion's spectrum over ``life_s`` (s): one bin per 1 m/s of wind from cut-in to
    cut-out and a standstill bin; returns it with each bin's wind (m/s; NaN for standstill)."""
    winds = np.arange(CUT_IN, CUT_OUT + 1.0)
    lo, hi = np.maximum(winds - 0.5, CUT_IN), np.minimum(winds + 0.5, CUT_OUT)
    share = weibull_cdf(hi) - weibull_cdf(lo)
    cube = (np.minimum(winds, RATED_WIND) ** 3 - CUT_IN**3) / (RATED_WIND**3 - CUT_IN**3)
    power = RATED_POWER * np.maximum(cube, 0.0)
    rotor = np.clip(ROTOR_RPM[1] * winds / RATED_WIND, *ROTOR_RPM)
    speed = rotor * RATIO * 2 * math.pi / 60  # the pinion's (rad/s)
    torque = power / speed
    idle = 1.0 - share.sum()
    spectrum = jr.LoadSpectrum(
        np.append(torque, 0.0), np.append(speed, 0.0), np.append(share, idle) * life_s
    )
    return spectrum, np.append(winds, np.nan)


def main(out_dir=DOCS) -> dict:
    """Rate the stage under the spectrum, write the figure and the record into ``out_dir``
    (default docs/bench; created if missing); returns the record."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rc = jio.rating_of(jio.load_case("nrel-5mw-stage3"))
    single = jr.rate(rc.geometry, rc.operating, rc.settings)
    spectrum, winds = wind_spectrum(float(rc.settings.life))
    settings = eqx.tree_at(lambda s: s.application_factor, rc.settings, 1.0)
    sr = jr.rate_spectrum(rc.geometry, spectrum, settings)
    hours = np.asarray(spectrum.duration) / 3600
    rec = {
        "wind_m_s": [None if np.isnan(w) else float(w) for w in winds],
        "torque_Nm": np.asarray(spectrum.torque).tolist(),
        "speed_rpm": (np.asarray(spectrum.speed) * 30 / math.pi).tolist(),
        "hours": hours.tolist(),
        "damage_H": np.asarray(sr.damage_H).tolist(),
        "damage_F": np.asarray(sr.damage_F).tolist(),
        "S_H_spectrum": np.asarray(sr.S_H).tolist(),
        "S_F_spectrum": np.asarray(sr.S_F).tolist(),
        "S_H_rated_KA_1.25": np.asarray(single.pitting.S_H).tolist(),
        "S_F_rated_KA_1.25": np.asarray(single.bending.S_F).tolist(),
        "life_h_pitting": [_finite(v) for v in np.asarray(sr.life_H) / 3600],
        "life_h_bending": [_finite(v) for v in np.asarray(sr.life_F) / 3600],
    }
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4), constrained_layout=True)
    on = ~np.isnan(winds)
    a.bar(winds[on], hours[on], width=0.8, color="0.7", label="hours in 20 years")
    a.set(xlabel="hub wind (m/s)", ylabel="hours", title="load spectrum (Rayleigh, mean 10 m/s)")
    t = a.twinx()
    t.plot(winds[on], np.asarray(spectrum.torque)[on] / 1e3, "k.-", label="pinion torque")
    t.set_ylabel("pinion torque (kN·m)")
    # at the actual loads no bin reaches the S-N lines (no damage, infinite life): the damage
    # shares are drawn at the loads scaled by the spectrum's S, where their sum is 1
    w = 0.2
    shares = {}
    for j, gear in enumerate(("pinion", "wheel")):
        shares[f"D_H {gear} at S_H"] = jr.miner_damage(
            sr.S_H[j] * sr.sigma_H[:, j], sr.cycles[:, j], sr.curves_H[j])
        shares[f"D_F {gear} at S_F"] = jr.miner_damage(
            sr.S_F[j] * sr.sigma_F[:, j], sr.cycles[:, j], sr.curves_F[j])
    for j, (name, d) in enumerate(shares.items()):
        b.bar(winds[on] + (j - 1.5) * w, np.asarray(d)[on], width=w, label=name)
    rec["damage_share_at_S"] = {k: np.asarray(v).tolist() for k, v in shares.items()}
    b.set(xlabel="hub wind (m/s)", ylabel="Miner damage n_i/N_i at S × the load",
          yscale="log", title=f"S_H {_pair(sr.S_H)}, S_F {_pair(sr.S_F)} (pinion / wheel)")
    b.set_ylim(bottom=1e-6)
    b.legend(fontsize=8)
    fig.suptitle("nrel-5mw-stage3 under a wind spectrum (ISO 6336-6, Palmgren–Miner)")
    fig.savefig(out_dir / "load_spectrum_wind.png", dpi=110)
    plt.close(fig)
    (out_dir / "load_spectrum_wind.json").write_text(json.dumps(rec, indent=1) + "\n")
    return rec


def _finite(v):
    return float(v) if np.isfinite(v) else None


def _pair(values) -> str:
    return " / ".join(f"{float(v):.3g}" for v in np.asarray(values))


if __name__ == "__main__":
    main(*sys.argv[1:2])
