"""Life under a load spectrum (ISO 6336-6:2019): Palmgren–Miner damage per bin on the rating's
own S–N lines, the safety factors on stress at which the damage sum reaches 1, and the life.

A spectrum (:class:`LoadSpectrum`) is a list of bins, each a pinion torque T_i (N·m), a
pinion speed ω_i (rad/s) and the time t_i (s) it runs there; :meth:`LoadSpectrum.from_cycles`
takes pinion load cycles instead of times, :meth:`LoadSpectrum.from_time_series` counts a
sampled torque (and speed) history into torque levels (time at level, no rainflow: a gear's
tooth sees one load cycle per mesh whatever the torque does in between).

Each bin is rated as an operating point (:func:`jaxgear.rating.rate`: its own K_v, K_Hβ, Z_v at its
torque and speed), which gives the bin's stresses σ_H,i and σ_F,i and the S–N line of each
gear (:class:`SNCurve`)::

    σ_HG(N) = σ_Hlim Z_NT(N) Z_L Z_v Z_R Z_W Z_X        (ISO 6336-2, Z_NT the material's)
    σ_FG(N) = σ_Flim Y_ST Y_NT(N) Y_δrelT Y_RrelT Y_X Y_M   (ISO 6336-3, Y_NT the material's)

    n_i = t_i ω_i / 2π × cycles per turn (the gear: / |u|),   N_i: σ_G(N_i) = σ_i
    D = Σ n_i / N_i  (Palmgren–Miner),   S: Σ n_i / N_i(S σ_i) = 1,   life = Σ t_i / D

The life factor's power law is continued above its static corner (the Z_NT of ISO 6336-6's
Annex C example reads 1.61 at 9.05·10⁴ cycles, above the table's 1.6 at 10⁵), up to the static
strength, where ISO 6336-2/-3 set the lubrication, roughness and size factors to 1
(σ_Hlim Z_NT,stat Z_W Z_X: 2400 N/mm² in the annex; bending σ_Flim Y_ST Y_NT,stat Y_δrelT Y_M):
a bin above it fails at once (N_i = 0, damage infinite). Beyond the curve's last corner
(10¹⁰ cycles, where the rating's Z_NT and Y_NT stay constant) a stress does no damage (N_i
infinite): the endurance limit of the rating's own lines. docs/rating.md, "Load spectrum and
life".
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import as_float, check_instance, check_real
from ._rate import check_rating_arguments, rate
from ._settings import OperatingPoint

__all__ = [
    "LoadSpectrum",
    "SNCurve",
    "SpectrumRating",
    "miner_damage",
    "rate_spectrum",
    "rate_train_spectrum",
    "spectrum_safety",
]

#: the bracket of the spectrum safety factor's search (its bisection in log S): a spectrum
#: whose damage stays below 1 at 1000 times its stresses reports S = inf
SAFETY_BRACKET = (1e-3, 1e3)


class LoadSpectrum(eqx.Module):
    """A load spectrum of k bins, (k,) each: pinion ``torque`` T_i (N·m, >= 0), pinion
    ``speed`` ω_i (rad/s, >= 0; a scalar for all bins) and ``duration`` t_i (s, >= 0) the
    time run in the bin (over the life the spectrum stands for). A bin with a zero torque,
    speed or duration does no damage (the standard's empty bins, a standstill).

    Raises:
        ValueError: a negative or non-finite entry (a reversing torque loads the other flank:
            not modelled), arrays of different lengths or not 1-D, no bin with torque, speed and
            duration all > 0; one line naming the argument, the entry and the allowed range.
    """

    torque: Float[Array, " k"]
    speed: Float[Array, " k"]
    duration: Float[Array, " k"]

    def __init__(self, torque, speed, duration):
        w = "LoadSpectrum"
        check_real("torque", torque, "N·m", lo=0.0, shape=(None,), shape_text="(k,)", where=w)
        k = np.shape(torque)[0]
        if k < 1:
            raise ValueError(f"{w}: torque has no bins: allowed (k,) with k >= 1")
        if np.ndim(speed) == 0:
            check_real("speed", speed, "rad/s", lo=0.0, where=w)
            speed = np.full(k, float(speed))
        check_real("speed", speed, "rad/s", lo=0.0, shape=(k,), shape_text=f"({k},), as torque",
                   where=w)
        check_real("duration", duration, "s", lo=0.0, shape=(k,),
                   shape_text=f"({k},), as torque", where=w)
        t, s, d = (np.asarray(v, dtype=float) for v in (torque, speed, duration))
        if not np.any((t > 0) & (s > 0) & (d > 0)):
            raise ValueError(
                f"{w}: no bin with torque, speed and duration all > 0: allowed at least one "
                "loaded, turning bin with time in it"
            )
        self.torque, self.speed, self.duration = as_float(t), as_float(s), as_float(d)

    @classmethod
    def from_cycles(cls, torque, speed, cycles) -> LoadSpectrum:
        """Bins given by pinion load cycles (turns) n_i instead of times: t_i = 2π n_i / ω_i.

        Raises:
            ValueError: as the constructor; a bin with cycles > 0 at speed 0 (one line)."""
        w = "LoadSpectrum.from_cycles"
        check_real("cycles", cycles, "", lo=0.0, shape=(None,), shape_text="(k,)", where=w)
        n = np.asarray(cycles, dtype=float)
        check_real("speed", speed, "rad/s", lo=0.0, where=w)
        s = np.broadcast_to(np.asarray(speed, dtype=float), n.shape)
        stopped = (n > 0) & (s <= 0)
        if np.any(stopped):
            i = int(np.argmax(stopped))
            raise ValueError(
                f"{w}: cycles[{i}] = {n[i]:g} at speed[{i}] = 0: allowed cycles only in a bin "
                "with speed > 0"
            )
        d = np.where(n > 0, 2 * math.pi * n / np.where(s > 0, s, 1.0), 0.0)
        return cls(torque, s, d)

    @classmethod
    def from_time_series(cls, torque, speed, time_step, bins=20) -> LoadSpectrum:
        """Count a sampled history into torque levels (time at level, ISO 6336-6's load
        duration distribution): sample j (torque T_j >= 0, speed ω_j, of ``time_step`` Δt s)
        falls in the level (e_m, e_{m+1}] of the edges e (the first level closed below); each
        non-empty level is a bin at its upper edge's torque (the conservative end, as the
        standard's tables list a level by its largest torque), its time the samples' m Δt and
        its speed Σ ω_j / m (so that its cycles are the samples' Σ ω_j Δt / 2π).

        Args:
            torque: (m,) pinion torque samples (N·m, >= 0). speed: (m,) pinion speed samples
                (rad/s, >= 0), or one speed for all. time_step: Δt (s, > 0).
            bins: the number of levels, equal widths from 0 to the largest torque (int >= 1), or
                their edges (increasing, the first <= 0 < the last; every sample inside).

        Raises:
            ValueError: a negative torque, a sample beyond the edges, edges not increasing,
                ``bins`` < 1; one line naming the argument."""
        w = "LoadSpectrum.from_time_series"
        check_real("torque", torque, "N·m", lo=0.0, shape=(None,), shape_text="(m,)", where=w)
        t = np.asarray(torque, dtype=float)
        if np.ndim(speed) == 0:
            check_real("speed", speed, "rad/s", lo=0.0, where=w)
            speed = np.full(t.shape, float(speed))
        check_real("speed", speed, "rad/s", lo=0.0, shape=t.shape,
                   shape_text=f"{t.shape}, as torque", where=w)
        check_real("time_step", time_step, "s", lo=0.0, lo_open=True, where=w)
        s = np.asarray(speed, dtype=float)
        if np.ndim(bins) == 0:
            if isinstance(bins, bool) or int(bins) != bins or bins < 1:
                raise ValueError(f"{w}: bins = {bins!r} is out of range: allowed an integer >= 1 "
                                 "or the levels' edges")
            edges = np.linspace(0.0, max(float(t.max()), 1e-300), int(bins) + 1)
        else:
            check_real("bins", bins, "N·m", shape=(None,), shape_text="(levels + 1,)", where=w)
            edges = np.asarray(bins, dtype=float)
            if edges.size < 2 or np.any(np.diff(edges) <= 0):
                raise ValueError(f"{w}: bins = {edges.tolist()} is out of range: allowed "
                                 "increasing edges, at least two")
            outside = (t < edges[0]) | (t > edges[-1])
            if np.any(outside):
                j = int(np.argmax(outside))
                raise ValueError(f"{w}: torque[{j}] = {t[j]:g} N·m is outside the edges "
                                 f"[{edges[0]:g}, {edges[-1]:g}]: allowed every sample inside")
        level = np.clip(np.searchsorted(edges, t, side="left") - 1, 0, edges.size - 2)
        count = np.bincount(level, minlength=edges.size - 1).astype(float)
        omega = np.bincount(level, weights=s, minlength=edges.size - 1)
        keep = count > 0
        return cls(edges[1:][keep], omega[keep] / count[keep], count[keep] * float(time_step))

    @property
    def cycles(self) -> Float[Array, " k"]:
        """Pinion turns per bin, t_i ω_i / 2π."""
        return self.duration * self.speed / (2 * jnp.pi)

    @property
    def total_duration(self) -> Float[Array, ""]:
        """Σ t_i (s)."""
        return jnp.sum(self.duration)

    def carried(self, torque_ratio, speed_ratio) -> LoadSpectrum:
        """The spectrum carried to another member by lossless ratios: every bin's torque times
        ``torque_ratio`` and speed times ``speed_ratio`` (each > 0), its time unchanged (a
        train's input spectrum at a mesh's driving gear: T_k/T_in and ω_k/ω_in; a planetary
        mesh's: per planet path, relative to the carrier).

        Raises:
            ValueError: a ratio not a finite number > 0 (one line)."""
        w = "LoadSpectrum.carried"
        check_real("torque_ratio", torque_ratio, lo=0.0, lo_open=True, where=w)
        check_real("speed_ratio", speed_ratio, lo=0.0, lo_open=True, where=w)
        return LoadSpectrum(np.asarray(self.torque) * float(torque_ratio),
                            np.asarray(self.speed) * float(speed_ratio),
                            np.asarray(self.duration))

    def scaled_to(self, life) -> LoadSpectrum:
        """The spectrum with its times scaled so that they add up to ``life`` (s, > 0): a
        sample of the duty (ISO 6336-6's Annex C: 70 days measured, scaled to 30 years).

        Raises:
            ValueError: ``life`` not a finite number > 0 (one line)."""
        check_real("life", life, "s", lo=0.0, lo_open=True, where="LoadSpectrum.scaled_to")
        d = np.asarray(self.duration) * float(life) / float(self.total_duration)
        return LoadSpectrum(self.torque, self.speed, d)


class SNCurve(eqx.Module):
    """An S–N line of ISO 6336's rating: σ(N) = ``reference`` × f(N), f the material's life
    factor (Z_NT or Y_NT), a power law between its ``points`` (:attr:`jaxgear.rating.
    AbstractTreatment.z_nt_points`); the first segment continued above the first corner up to
    the ``static`` strength (the ceiling); beyond the last corner constant (the endurance
    limit, no damage below it).

    Attributes:
        points: ((N, f), ...) the life factor's corners, N increasing, f decreasing (static).
        reference: σ at f = 1 (Pa): σ_Hlim Z_L Z_v Z_R Z_W Z_X for pitting, σ_Flim Y_ST Y_δrelT
            Y_RrelT Y_X Y_M for bending; an array broadcasts (one per bin).
        static: the static strength (Pa), σ_lim f(N_1) with ISO's static factors; broadcasts.

    Raises:
        ValueError: fewer than two points, N not increasing or f not decreasing, reference or
            static not > 0 (one line).
    """

    points: tuple = eqx.field(static=True)
    reference: Array
    static: Array

    def __init__(self, points, reference, static):
        w = "SNCurve"
        pts = tuple((float(n), float(f)) for n, f in points)
        ns, fs = np.array([p[0] for p in pts]), np.array([p[1] for p in pts])
        if len(pts) < 2 or np.any(np.diff(ns) <= 0) or np.any(np.diff(fs) >= 0) or ns[0] < 1:
            raise ValueError(f"{w}: points = {pts} is out of range: allowed two or more (N, f) "
                             "with N >= 1 increasing and f decreasing")
        check_real("reference", reference, "Pa", lo=0.0, lo_open=True, where=w)
        check_real("static", static, "Pa", lo=0.0, lo_open=True, where=w)
        self.points = pts
        self.reference, self.static = as_float(reference), as_float(static)

    @property
    def endurance(self) -> Array:
        """σ at the last corner (Pa): below it, no damage."""
        return self.reference * self.points[-1][1]

    def _logs(self, dtype):
        ln = jnp.log(jnp.asarray([p[0] for p in self.points], dtype=dtype))
        lf = jnp.log(jnp.asarray([p[1] for p in self.points], dtype=dtype))
        return ln, lf

    def stress(self, cycles) -> Array:
        """σ(N) (Pa) at ``cycles`` N (> 0): the curve as above, at most :attr:`static`."""
        n = jnp.log(jnp.maximum(jnp.asarray(cycles, dtype=self.reference.dtype), 1.0))
        ln, lf = self._logs(n.dtype)
        k0 = (lf[0] - lf[1]) / (ln[1] - ln[0])
        f = jnp.where(n < ln[0], lf[0] + k0 * (ln[0] - n), jnp.interp(n, ln, lf))
        return jnp.minimum(self.reference * jnp.exp(f), self.static)

    def cycles_to_failure(self, stress) -> Array:
        """N(σ): the load cycles to failure at ``stress`` (Pa): 0 above :attr:`static`, inf
        below :attr:`endurance`, else the curve's inverse."""
        s = jnp.asarray(stress, dtype=self.reference.dtype)
        r = jnp.log(jnp.maximum(s, 1e-300) / self.reference)
        ln, lf = self._logs(r.dtype)
        k0 = (lf[0] - lf[1]) / (ln[1] - ln[0])
        inside = jnp.interp(r, lf[::-1], ln[::-1])
        log_n = jnp.where(r > lf[0], ln[0] - (r - lf[0]) / k0, inside)
        n = jnp.exp(log_n)
        n = jnp.where(s > self.static, 0.0, n)
        return jnp.where(s < self.endurance, jnp.inf, n)


def miner_damage(stress, cycles, curve: SNCurve) -> Array:
    """Palmgren–Miner damage n_i / N_i of each bin: ``cycles`` n_i at ``stress`` σ_i (Pa) on
    ``curve`` (:meth:`SNCurve.cycles_to_failure`); 0 where n_i = 0 or σ_i is below the
    endurance limit, inf above the static strength. Shapes broadcast (ISO 6336-6:2019)."""
    n_fail = curve.cycles_to_failure(stress)
    n = jnp.asarray(cycles)
    return jnp.where(n > 0, n / jnp.where(n > 0, n_fail, 1.0), 0.0)


def spectrum_safety(stress, cycles, curve: SNCurve, axis: int = 0) -> Array:
    """The safety factor S on stress under a spectrum: the factor on every bin's ``stress``
    at which the Miner sum over ``axis`` of ``cycles``/N(S σ) reaches 1 (ISO 6336-6: the
    spectrum's S_H or S_F), found by bisection in log S within :data:`SAFETY_BRACKET`; inf
    where the sum stays below 1 at its top (no bin reaches the S–N line).

    One bin of n cycles gives σ(n)/σ, the single-point rating's S at a life of n cycles."""
    s, n = jnp.asarray(stress), jnp.asarray(cycles)

    def total(factor):
        return jnp.sum(miner_damage(jnp.expand_dims(factor, axis) * s, n, curve), axis=axis)

    lo, hi = (math.log(v) for v in SAFETY_BRACKET)
    shape = jnp.sum(s * n, axis=axis).shape

    def halve(_, ab):  # the bracket's 13.8 halved 64 times: below float64's resolution
        a, b = ab
        m = (a + b) / 2
        below = total(jnp.exp(m)) < 1.0
        return jnp.where(below, m, a), jnp.where(below, b, m)

    a, b = jax.lax.fori_loop(0, 64, halve, (jnp.full(shape, lo), jnp.full(shape, hi)))
    return jnp.where(total(jnp.exp(jnp.full(shape, hi))) < 1.0, jnp.inf, jnp.exp((a + b) / 2))


class SpectrumRating(eqx.Module):
    """A rating under a load spectrum (:func:`rate_spectrum`), per bin and gear (k, 2) unless
    stated:

    Attributes:
        spectrum: the :class:`LoadSpectrum`. cycles: load cycles n_i of each gear's rated flank.
        sigma_H, sigma_F: the bins' contact and root stresses (Pa; 0 in an idle bin).
        cycles_to_failure_H, cycles_to_failure_F: N_i on each gear's S–N line (inf: below the
            endurance limit or an idle bin).
        damage_H, damage_F: n_i / N_i.
        S_H, S_F: (2,) the safety factors on stress at which the damage sum is 1.
        curves_H, curves_F: each gear's :class:`SNCurve` (pinion, gear), a reference per bin.
    """

    spectrum: LoadSpectrum
    cycles: Array
    sigma_H: Array
    sigma_F: Array
    cycles_to_failure_H: Array
    cycles_to_failure_F: Array
    damage_H: Array
    damage_F: Array
    S_H: Array
    S_F: Array
    curves_H: tuple
    curves_F: tuple

    @property
    def damage_sum_H(self) -> Array:
        """(2,) Σ n_i/N_i for pitting over the spectrum."""
        return jnp.sum(self.damage_H, axis=0)

    @property
    def damage_sum_F(self) -> Array:
        """(2,) Σ n_i/N_i for bending."""
        return jnp.sum(self.damage_F, axis=0)

    @property
    def life_H(self) -> Array:
        """(2,) the time (s) to a pitting damage of 1, the spectrum repeated: Σ t_i / D."""
        return self.spectrum.total_duration / self.damage_sum_H

    @property
    def life_F(self) -> Array:
        """(2,) the time (s) to a bending damage of 1."""
        return self.spectrum.total_duration / self.damage_sum_F

    def summary(self) -> dict:
        """The ``rating.spectrum`` section of ``summary.json``: per bin lists (per gear
        [pinion, gear] pairs), SI units but speed in rpm and times in hours; an infinite N_i,
        S or life as ``null``."""

        def v(a):
            a = np.asarray(a, dtype=float)
            out = np.where(np.isfinite(a), a, np.nan).tolist()
            return _nulls(out)

        sp = self.spectrum
        return {
            "method": "ISO 6336-6:2019 Palmgren-Miner on the rating's S-N lines (Z_NT, Y_NT)",
            "bins": {
                "torque_Nm": v(sp.torque),
                "speed_rpm": v(sp.speed * 30 / np.pi),
                "hours": v(sp.duration / 3600),
                "cycles": v(self.cycles),
            },
            "pitting": {
                "sigma_H_Pa": v(self.sigma_H),
                "cycles_to_failure": v(self.cycles_to_failure_H),
                "damage": v(self.damage_H),
                "damage_sum": v(self.damage_sum_H),
                "S_H": v(self.S_H),
                "life_h": v(self.life_H / 3600),
            },
            "bending": {
                "sigma_F_Pa": v(self.sigma_F),
                "cycles_to_failure": v(self.cycles_to_failure_F),
                "damage": v(self.damage_F),
                "damage_sum": v(self.damage_sum_F),
                "S_F": v(self.S_F),
                "life_h": v(self.life_F / 3600),
            },
        }


def _nulls(x):
    if isinstance(x, list):
        return [_nulls(e) for e in x]
    return None if math.isnan(x) else x


_RATE = eqx.filter_jit(rate)


def rate_spectrum(geometry, spectrum: LoadSpectrum, settings) -> SpectrumRating:
    """Rate a pair under a load spectrum (ISO 6336-6:2019, module docstring): each bin rated at
    its torque and speed (:func:`jaxgear.rating.rate`, the settings as given: ISO 6336-6 takes K_A =
    1 when the spectrum holds the driving and driven machines' loads, so pass
    ``application_factor=1`` then), its damage on each gear's S–N lines, the safety factors at a
    damage sum of 1 and the life.

    Args:
        geometry: :class:`jaxgear.rating.RatingGeometry` or
            :class:`jaxgear.rating.InternalRatingGeometry`.
        spectrum: :class:`LoadSpectrum` (pinion torque and speed per bin). settings:
            :class:`jaxgear.rating.RatingSettings` (its ``life`` cancels: each bin's cycles are its
            own, n_i = t_i ω_i / 2π × the gear's cycles per pinion turn).

    Returns:
        :class:`SpectrumRating`. Concrete values only (each bin is rated by a jitted
        :func:`jaxgear.rating.rate` in turn, an idle bin skipped), not under ``jit`` as a whole; its
        parts :func:`miner_damage` and :func:`spectrum_safety` are pure ``jax.numpy``.

    Raises:
        ValueError: an argument of the wrong kind (one line naming it)."""
    check_instance("spectrum", spectrum, LoadSpectrum, "a jaxgear.rating.LoadSpectrum",
                   "rate_spectrum")
    t0, w0 = float(jnp.max(spectrum.torque)), float(jnp.max(spectrum.speed))
    check_rating_arguments("rate_spectrum", geometry, OperatingPoint(t0, w0), settings)
    active = (spectrum.torque > 0) & (spectrum.speed > 0) & (spectrum.duration > 0)
    rows = []
    for i in range(spectrum.torque.shape[0]):
        on = bool(active[i])
        t = spectrum.torque[i] if on else t0
        w = spectrum.speed[i] if on else w0
        rows.append(_RATE(geometry, OperatingPoint(t, w), settings))
    p = _stack([r.pitting for r in rows])
    b = _stack([r.bending for r in rows])
    on = active[:, None]
    # each bin's load cycles per gear: the rating's N_L over its life, scaled to the bin's time
    n = jnp.where(on, p.cycles * (spectrum.duration / settings.life)[:, None], 0.0)
    sig_h = jnp.where(on, p.sigma_H, 0.0)
    sig_f = jnp.where(on, b.sigma_F, 0.0)
    ref_h = p.sigma_HG / p.Z_NT
    ref_f = b.sigma_FG / b.Y_NT
    stat_h = ref_h / (p.Z_L * p.Z_v * p.Z_R)[:, None]  # ISO 6336-2: Z_L Z_v Z_R = 1 at static
    stat_f = ref_f / (b.Y_R_rel_T * b.Y_X)  # ISO 6336-3: Y_RrelT = Y_X = 1 at static
    curves_h, curves_f, out = [], [], {k: [] for k in ("nh", "nf", "dh", "df", "sh", "sf")}
    for j, tr in enumerate(settings.material.treatment.per_gear()):
        ch = SNCurve(tr.z_nt_points, ref_h[:, j], stat_h[:, j] * tr.z_nt_points[0][1])
        cf = SNCurve(tr.y_nt_points, ref_f[:, j], stat_f[:, j] * tr.y_nt_points[0][1])
        curves_h.append(ch)
        curves_f.append(cf)
        for key, value in _gear_columns(ch, cf, sig_h[:, j], sig_f[:, j], n[:, j], active).items():
            out[key].append(value)
    cols = {k: jnp.stack(v, axis=-1) for k, v in out.items()}
    return SpectrumRating(
        spectrum=spectrum,
        cycles=n,
        sigma_H=sig_h,
        sigma_F=sig_f,
        cycles_to_failure_H=cols["nh"],
        cycles_to_failure_F=cols["nf"],
        damage_H=cols["dh"],
        damage_F=cols["df"],
        S_H=cols["sh"],
        S_F=cols["sf"],
        curves_H=tuple(curves_h),
        curves_F=tuple(curves_f),
    )


@eqx.filter_jit
def _gear_columns(ch: SNCurve, cf: SNCurve, sig_h, sig_f, n, active) -> dict:
    """One gear's N_i, damage per bin and spectrum safety factors, pitting and bending."""
    return {
        "nh": jnp.where(active, ch.cycles_to_failure(sig_h), jnp.inf),
        "nf": jnp.where(active, cf.cycles_to_failure(sig_f), jnp.inf),
        "dh": miner_damage(sig_h, n, ch),
        "df": miner_damage(sig_f, n, cf),
        "sh": spectrum_safety(sig_h, n, ch),
        "sf": spectrum_safety(sig_f, n, cf),
    }


def _stack(results):
    """The bins' results stacked along a first axis (arrays only)."""
    first = results[0]
    arrays = {}
    for name in ("sigma_H", "sigma_HG", "Z_NT", "Z_L", "Z_v", "Z_R", "cycles", "sigma_F",
                 "sigma_FG", "Y_NT", "Y_R_rel_T", "Y_X"):
        if hasattr(first, name):
            arrays[name] = jnp.stack([jnp.asarray(getattr(r, name)) for r in results])
    return SimpleNamespace(**arrays)


def rate_train_spectrum(meshes, spectrum: LoadSpectrum, reference) -> tuple[SpectrumRating, ...]:
    """Rate every mesh of a gear train or a planetary stage under the load spectrum of its
    input (ISO 6336-6:2019, module docstring): each mesh's bins are the input's carried to its
    driving member by the lossless ratios of its operating point to the input's
    (:meth:`LoadSpectrum.carried`: T_i T_k/T_ref, ω_i ω_k/ω_ref), each bin rated at its torque
    and speed as the mesh's single-point rating is (:func:`rate_spectrum`).

    Args:
        meshes: (geometry, operating, settings) of each mesh: its single-point rating's
            arguments at the input's ``reference`` point (:func:`jaxgear.io.ratings_of`' for a
            train case: its driving gear's torque and speed; a planetary stage's: one planet
            path's torque and the driving member's speed relative to the carrier, the load
            sharing factor in the settings, :func:`jaxgear.rating.with_load_sharing`).
        spectrum: :class:`LoadSpectrum` of the input member (torque and speed per bin).
        reference: :class:`jaxgear.rating.OperatingPoint`, the input's torque (N·m) and speed
            (rad/s) at which ``meshes``' operating points hold, each > 0.

    Returns:
        A :class:`SpectrumRating` per mesh (pinion / gear = driving / driven).

    Raises:
        ValueError: a reference not an OperatingPoint or not > 0, a mesh not three items, as
            :func:`rate_spectrum` (one line naming the argument)."""
    w = "rate_train_spectrum"
    check_instance("spectrum", spectrum, LoadSpectrum, "a jaxgear.rating.LoadSpectrum", w)
    check_instance("reference", reference, OperatingPoint,
                   "a jaxgear.rating.OperatingPoint(torque, speed) of the input", w)
    t_ref, w_ref = float(reference.torque), float(reference.speed)
    for name, v in (("reference.torque", t_ref), ("reference.speed", w_ref)):
        check_real(name, v, lo=0.0, lo_open=True, where=w)
    out = []
    for k, mesh in enumerate(meshes):
        if not isinstance(mesh, tuple | list) or len(mesh) != 3:
            raise ValueError(f"{w}: meshes[{k}] = {type(mesh).__name__}: allowed a (geometry, "
                             "operating, settings) triple")
        geometry, operating, settings = mesh
        check_instance(f"meshes[{k}] operating", operating, OperatingPoint,
                       "a jaxgear.rating.OperatingPoint", w)
        carried = spectrum.carried(abs(float(operating.torque)) / t_ref,
                                   abs(float(operating.speed)) / w_ref)
        out.append(rate_spectrum(geometry, carried, settings))
    return tuple(out)
