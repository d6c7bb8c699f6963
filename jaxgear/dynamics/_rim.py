"""The rim of a hybrid run: the stations of every condensed member in the records
(:func:`rim_stations`, :func:`_rim_of`) and their nodal-diameter waves (:func:`rim_waves`, the
seed's (3.2) Fourier series)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..scenes import HybridPair

__all__ = ["rim_stations", "rim_waves"]


def _rim_of(scene: HybridPair):
    """X ↦ (radial, axial) displacement of the rim stations of every condensed member, member
    after member (each in its own body frame, at the axial master plane nearest mid-face:
    :meth:`~jaxgear.scenes.GearMember.rim_stations`), each (Σ Z,); (0,) when every member is
    rigid. A pair with a flexible wheel: the wheel's Z stations; both members flexible: the
    pinion's z1 stations, then the wheel's (:func:`rim_stations` splits them)."""
    dtype = scene.structure.K.dtype
    stations = [m.rim_stations() for m in scene.gear_members()]
    rim = jnp.concatenate([jnp.zeros((0, 3), jnp.int32)] + [s.dofs for s in stations])
    ang = jnp.concatenate([jnp.zeros((0,), dtype)] + [s.angles for s in stations])

    def rim_of(X):
        u = X[rim]
        return u[:, 0] * jnp.cos(ang) + u[:, 1] * jnp.sin(ang), u[:, 2]

    return rim_of


def rim_stations(scene) -> list[tuple[int, slice]]:
    """Where each condensed member's stations sit in a hybrid run's rim records
    (:attr:`~jaxgear.dynamics.DynamicResponse.rim_radial`, ``rim_axial``): (member index, the
    slice of its Z stations) per member with rim stations
    (:meth:`~jaxgear.scenes.GearMember.rim_stations`), in member order; [] for a rigid scene."""
    out, start = [], 0
    for i, member in enumerate(scene.gear_members()):
        Z = member.rim_stations().count
        if Z:
            out.append((i, slice(start, start + Z)))
            start += Z
    return out


def rim_waves(u, time_step, spin: float = -1.0, band=None) -> dict:
    """Nodal-diameter content of a rim field (the seed's (3.2) Fourier series in the angle, then
    in time): which diameters vibrate, at what frequency, travelling which way.

    Args:
        u: rim displacement at Z equally spaced stations (body frame, station k at angle
            2πk/Z), over equally spaced steps, shape (S, Z)
            (:class:`~jaxgear.dynamics.DynamicResponse` ``rim_radial`` or ``rim_axial``, NumPy).
        time_step: Δt (s). spin: the body's rotation sense about z (−1 for the wheel, +1 for the
            pinion): a wave travelling the same way is *forward*.
        band: (f_min, f_max) (Hz): look for each diameter's largest wave in this band only
            (e.g. above half the mesh frequency, to skip the quasi-static load pattern that
            travels round the turning body at n times its rotation frequency). Default: all.

    Returns:
        dict of NumPy arrays over the nodal diameters n = 0 … Z/2: ``nodal_diameter``,
        ``amplitude`` (m, the largest travelling-wave amplitude of that diameter),
        ``frequency_hz`` (of that wave, in the body frame) and ``direction`` (+1 forward,
        −1 backward, 0 for n = 0 or a standing pattern). The mean over time is removed.
    """
    u = np.asarray(u, dtype=float)
    S, Z = u.shape
    if S < 4 or Z < 3:
        raise ValueError(f"rim field of shape {u.shape}: need >= 4 steps and >= 3 stations")
    u = u - u.mean(axis=0, keepdims=True)
    # spatial harmonics U_n(t) = (2/Z) Σ_k u_k e^{−i n φ_k}: a wave A cos(nφ − ωt) (towards +φ)
    # gives U_n = A e^{−iωt}, one towards −φ gives A e^{+iωt}
    U = np.fft.fft(u, axis=1)[:, : Z // 2 + 1] * (2.0 / Z)
    spec = np.fft.fft(U, axis=0) / S  # (S, n): frequency bins ν_j, e^{+i 2π ν t} convention
    freq = np.fft.fftfreq(S, time_step)
    inside = np.ones(S, bool)
    if band is not None:
        inside = (np.abs(freq) >= band[0]) & (np.abs(freq) <= band[1])
        if not inside.any():
            raise ValueError(f"band = {tuple(band)} Hz holds no frequency bin of the record")
    j = np.argmax(np.where(inside[:, None], np.abs(spec), -1.0), axis=0)
    amp = np.abs(spec[j, np.arange(spec.shape[1])])
    f = freq[j]
    # e^{−iωt} (towards +φ) appears at negative ν: direction +φ when ν < 0
    towards_plus = np.where(f < 0, 1.0, np.where(f > 0, -1.0, 0.0))
    direction = towards_plus * np.sign(spin)
    direction[0] = 0.0
    return {
        "nodal_diameter": np.arange(spec.shape[1]),
        "amplitude": amp,
        "frequency_hz": np.abs(f),
        "direction": direction,
    }
