"""Radiated sound power from a precomputed radiation resistance matrix, in JAX.

The power radiated by a surface whose vertices vibrate with complex normal velocity amplitudes
v (m/s, peak) is the quadratic form W = Re(vᴴ R v) (W) with R the radiation resistance matrix of
the surface at that frequency (kg/s; :func:`fem_prep.acoustics.radiation_resistance`, by the
BEM or the Rayleigh integral). R does not depend on the gear design: once it is cached, W and
its gradient with respect to everything upstream of v (tooth modifications → transmission
error → gearbox → housing velocity) are one differentiable JAX program. In the low-rank form
R ≈ L Lᴴ (the r radiation modes, L ``(n, r)``), W = ‖Lᴴ v‖², O(n r) per design instead of
O(n²).

Levels: the sound power level L_W = 10 log10(W / 1 pW) dB (ISO 3744 §3.6) and the sound
pressure level L_p = 10 log10(p_rms² / (20 µPa)²) dB; the radiation efficiency
σ = W / (ρc S ⟨v²⟩) with S ⟨v²⟩ = ½ vᴴ M v (M the P1 mass matrix), the equivalent radiated
power's denominator (Fahy & Gardonio, *Sound and Structural Vibration*, 2nd ed., §2.6).
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = [
    "P_REF",
    "W_REF",
    "radiated_power",
    "radiated_power_low_rank",
    "radiation_efficiency",
    "sound_power_level",
    "sound_pressure_level",
]

#: the reference sound power, 1 pW (ISO 80000-8)
W_REF = 1e-12
#: the reference sound pressure in air, 20 µPa (ISO 80000-8)
P_REF = 20e-6


def _last_axis(name, a, n, fn):
    if a.shape[-1:] != (n,):
        raise ValueError(f"{fn}: {name} must end in an axis of {n} (the vertices), got {a.shape}")


def radiated_power(velocity, resistance):
    """W = Re(vᴴ R v) (W).

    Args:
        velocity: ``(..., n)`` complex normal velocity amplitudes on the vertices (m/s, peak).
        resistance: ``(..., n, n)`` Hermitian R (kg/s), broadcast against ``velocity``'s
            leading axes (one per frequency, say).

    Returns:
        ``(...)`` the radiated power (W).

    Raises:
        ValueError: ``resistance`` not square or not of the velocity's size.
    """
    v = jnp.asarray(velocity)
    R = jnp.asarray(resistance)
    if R.ndim < 2 or R.shape[-1] != R.shape[-2]:
        raise ValueError(f"radiated_power: resistance must be (..., n, n), got {R.shape}")
    _last_axis("velocity", v, R.shape[-1], "radiated_power")
    return jnp.real(jnp.einsum("...i,...ij,...j->...", jnp.conj(v), R, v))


def radiated_power_low_rank(velocity, factors):
    """W = ‖Lᴴ v‖² (W) with R ≈ L Lᴴ (``RadiationResistance.factors``).

    Args:
        velocity: ``(..., n)`` complex normal velocity amplitudes on the vertices (m/s, peak).
        factors: ``(..., n, r)`` complex L ((kg/s)^½).

    Returns:
        ``(...)`` the radiated power (W).

    Raises:
        ValueError: ``factors`` not of the velocity's size.
    """
    v = jnp.asarray(velocity)
    L = jnp.asarray(factors)
    if L.ndim < 2:
        raise ValueError(f"radiated_power_low_rank: factors must be (..., n, r), got {L.shape}")
    _last_axis("velocity", v, L.shape[-2], "radiated_power_low_rank")
    a = jnp.einsum("...ir,...i->...r", jnp.conj(L), v)
    return jnp.sum(jnp.real(a) ** 2 + jnp.imag(a) ** 2, axis=-1)


def radiation_efficiency(velocity, resistance, mass_matrix, density, sound_speed):
    """σ = W / (ρc · ½ vᴴ M v): the radiated power over that of a large flat piston with the
    surface's area and mean square velocity (the equivalent radiated power).

    Args:
        velocity: ``(..., n)`` complex vertex normal velocity amplitudes (m/s, peak).
        resistance: ``(..., n, n)`` R (kg/s).
        mass_matrix: ``(n, n)`` the surface's P1 mass matrix (m²;
            ``RadiatingSurface.mass_matrix()``).
        density, sound_speed: the fluid's ρ (kg/m³) and c (m/s), > 0.

    Returns:
        ``(...)`` σ (1).

    Raises:
        ValueError: ρ or c ≤ 0, shapes that do not fit.
    """
    for name, x in (("density", density), ("sound_speed", sound_speed)):
        if not x > 0:
            raise ValueError(f"radiation_efficiency: {name} must be > 0, got {x!r}")
    M = jnp.asarray(mass_matrix)
    v = jnp.asarray(velocity)
    if M.ndim != 2 or M.shape[0] != M.shape[1]:
        raise ValueError(f"radiation_efficiency: mass_matrix must be (n, n), got {M.shape}")
    _last_axis("velocity", v, M.shape[0], "radiation_efficiency")
    erp = 0.5 * density * sound_speed * jnp.real(jnp.einsum("...i,ij,...j->...", jnp.conj(v), M, v))
    return radiated_power(v, resistance) / erp


def sound_power_level(power):
    """L_W = 10 log10(W / 1 pW) (dB re 1 pW) of ``power`` (W, > 0 for a finite level)."""
    return 10.0 * jnp.log10(jnp.asarray(power) / W_REF)


def sound_pressure_level(pressure):
    """L_p = 10 log10(|p|²/2 / (20 µPa)²) (dB re 20 µPa) of complex pressure amplitudes
    ``pressure`` (Pa, peak; the rms is |p|/√2)."""
    p = jnp.asarray(pressure)
    return 10.0 * jnp.log10(0.5 * (jnp.real(p) ** 2 + jnp.imag(p) ** 2) / P_REF**2)
