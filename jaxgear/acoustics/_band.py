"""Sound power and microphone pressure at any frequency of a band, from the radiation operators
computed at a grid of frequencies (:func:`fem_prep.acoustics.radiation_resistance`), in JAX.

A gear's orders sweep the frequency with the speed, so the radiated power is wanted at
frequencies nobody computes R at. Between two grid frequencies f_i < f < f_{i+1} the quadratic
forms W_i = vᴴ R(f_i) v and the mean square pressures at the microphones are interpolated
log-log (geometrically):

    W(f) ≈ W_i^{1−t} W_{i+1}^t,   t = log(f/f_i) / log(f_{i+1}/f_i),

which is exact for a power law W ∝ f^m: the low-frequency radiation of a compact source (a
monopole's W ∝ f², a dipole's ∝ f⁴ at fixed velocity) and the constant ρc S ⟨v²⟩ above
coincidence. A value of zero at either end falls back to linear interpolation. At a grid
frequency the value is exact; outside the grid it is NaN (no extrapolation).

The radiated intensity on the surface, I_j = Re(v_j* (R v)_j) / A_j (W/m², A_j the vertex's
share of the area), whose sum Σ_j I_j A_j is W, follows the same rule: its pattern is linear in
t between the two grid frequencies and scaled so that its sum is the log-log W above
(:func:`radiated_intensity_at`), so the map's total is the printed power at every frequency.

The velocity v is in the convention of R (fem_prep.acoustics: e^{-iωt}); the one-sided
amplitudes of jaxgear's whine and housing response (v(t) = Re v e^{iωt}) are its conjugates.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

__all__ = ["mean_square_pressure_at", "radiated_intensity_at", "radiated_power_at"]


def _bracket(frequency, grid):
    """The grid interval ``i`` (clipped to [0, G − 2]), the log-position ``t`` in it and
    whether the frequency lies in the grid's range (relative tolerance 1e-9)."""
    g = jnp.asarray(grid)
    f = jnp.asarray(frequency, g.dtype)
    G = g.shape[0]
    if G == 1:
        ok = jnp.abs(f - g[0]) <= 1e-9 * g[0]
        return jnp.zeros(f.shape, int), jnp.zeros(f.shape, g.dtype), ok
    i = jnp.clip(jnp.searchsorted(g, f, side="right") - 1, 0, G - 2)
    lo, hi = g[i], g[i + 1]
    ok = (f >= g[0] * (1 - 1e-9)) & (f <= g[-1] * (1 + 1e-9))
    fc = jnp.clip(f, lo, hi)
    t = jnp.log(fc / lo) / jnp.log(hi / lo)
    return i, t, ok


def _loglog(a, b, t):
    """a^{1−t} b^t for a, b ≥ 0 (linear where either is 0), safe for gradients."""
    pos = (a > 0) & (b > 0)
    sa, sb = jnp.where(pos, a, 1.0), jnp.where(pos, b, 1.0)
    geo = jnp.exp((1 - t) * jnp.log(sa) + t * jnp.log(sb))
    return jnp.where(pos, geo, (1 - t) * a + t * b)


def _interpolated(v, frequency_hz, grid, measure):
    """``measure(k, v)`` (a non-negative quadratic form of one velocity ``v`` (n,) at grid
    frequency k: a scalar or (q,)) of every velocity of ``v`` (..., n) at its frequency,
    log-log between the two bracketing grid frequencies; NaN outside the grid's range."""
    lead = v.shape[:-1]
    f = jnp.broadcast_to(jnp.asarray(frequency_hz, grid.dtype), lead)
    i, t, ok = _bracket(f, grid)
    j = jnp.minimum(i + 1, grid.shape[0] - 1)

    def one(args):
        vk, ik, jk = args
        return measure(ik, vk), measure(jk, vk)

    n = v.shape[-1]
    a, b = jax.lax.map(one, (v.reshape(-1, n), i.reshape(-1), j.reshape(-1)))
    tail = a.shape[1:]
    a, b = a.reshape(*lead, *tail), b.reshape(*lead, *tail)
    extra = (None,) * len(tail)
    return jnp.where(ok[(..., *extra)], _loglog(a, b, t[(..., *extra)]), jnp.nan)


def _check(fn, v, op, grid, what, vertex_axis):
    """The operator ``op`` (G, ., .) at the grid's G frequencies, the grid (G,), and the
    velocity ``v`` ending in the operator's vertex count (its axis ``vertex_axis``)."""
    if op.ndim != 3 or op.shape[0] != grid.shape[0]:
        raise ValueError(
            f"{fn}: {what} must be (G, ., .) with G = {grid.shape[0]} grid frequencies, "
            f"got {op.shape}"
        )
    if grid.ndim != 1 or grid.shape[0] < 1:
        raise ValueError(f"{fn}: grid_hz must be (G,) with G >= 1, got {grid.shape}")
    n = op.shape[vertex_axis]
    if v.shape[-1] != n:
        raise ValueError(f"{fn}: velocity must end in {n} (the vertices), got {v.shape}")


def radiated_power_at(velocity, frequency_hz, factors, grid_hz):
    """The radiated power W (W) of vertex normal velocities at frequencies between the grid's,
    interpolated log-log (module docstring) from W_i = ‖L_iᴴ v‖² at the two grid frequencies
    that bracket each frequency.

    Args:
        velocity: ``(..., n)`` complex vertex normal velocity amplitudes (m/s, peak; e^{-iωt}).
        frequency_hz: ``(...)`` the frequency of each velocity (Hz).
        factors: ``(G, n, r)`` L with R ≈ L Lᴴ at each grid frequency
            (``RadiationResistance.factors``, (kg/s)^½).
        grid_hz: ``(G,)`` the grid frequencies, increasing (Hz).

    Returns:
        ``(...)`` W (W); NaN at a frequency outside [grid_hz[0], grid_hz[-1]].

    Raises:
        ValueError: shapes that do not fit.
    """
    L = jnp.asarray(factors)
    grid = jnp.asarray(grid_hz, L.real.dtype)
    v = jnp.asarray(velocity)
    _check("radiated_power_at", v, L, grid, "factors", 1)
    return _interpolated(v, frequency_hz, grid,
                         lambda k, vk: jnp.sum(jnp.abs(jnp.conj(L[k]).T @ vk) ** 2))


def mean_square_pressure_at(velocity, frequency_hz, transfer, grid_hz):
    """The mean square pressure p_rms² = |p|²/2 (Pa²) at field points (microphones) of vertex
    normal velocities at frequencies between the grid's, interpolated log-log (module
    docstring) from |T_i v|²/2 at the two bracketing grid frequencies. L_p follows as
    10 log10(p_rms² / (20 µPa)²).

    Args:
        velocity: ``(..., n)`` complex vertex normal velocity amplitudes (m/s, peak; e^{-iωt}).
        frequency_hz: ``(...)`` (Hz).
        transfer: ``(G, q, n)`` T with p = T v at each grid frequency
            (``RadiationResistance.transfer``, Pa s/m).
        grid_hz: ``(G,)`` increasing (Hz).

    Returns:
        ``(..., q)`` p_rms² (Pa²); NaN outside the grid's range.

    Raises:
        ValueError: shapes that do not fit.
    """
    T = jnp.asarray(transfer)
    grid = jnp.asarray(grid_hz, T.real.dtype)
    v = jnp.asarray(velocity)
    _check("mean_square_pressure_at", v, T, grid, "transfer", 2)
    return _interpolated(v, frequency_hz, grid, lambda k, vk: 0.5 * jnp.abs(T[k] @ vk) ** 2)


def radiated_intensity_at(velocity, frequency_hz, factors, grid_hz, vertex_areas):
    """The radiated intensity I (W/m²) at each vertex of vertex normal velocities at
    frequencies between the grid's: I_j = Re(v_j* (R v)_j) / A_j at the two bracketing grid
    frequencies, linear in the log-position t between them and scaled so that Σ_j I_j A_j is
    :func:`radiated_power_at`'s W (module docstring).

    Args:
        velocity: ``(..., n)`` complex vertex normal velocity amplitudes (m/s, peak; e^{-iωt}).
        frequency_hz: ``(...)`` (Hz).
        factors: ``(G, n, r)`` L with R ≈ L Lᴴ (``RadiationResistance.factors``).
        grid_hz: ``(G,)`` increasing (Hz).
        vertex_areas: ``(n,)`` each vertex's share of the surface's area (m², > 0; a third of
            each triangle round it).

    Returns:
        ``(..., n)`` I (W/m²; negative where the surface draws power back); NaN outside the
        grid's range.

    Raises:
        ValueError: shapes that do not fit.
    """
    L = jnp.asarray(factors)
    grid = jnp.asarray(grid_hz, L.real.dtype)
    v = jnp.asarray(velocity)
    _check("radiated_intensity_at", v, L, grid, "factors", 1)
    a = jnp.asarray(vertex_areas, L.real.dtype)
    if a.shape != (L.shape[1],):
        raise ValueError(f"radiated_intensity_at: vertex_areas must be ({L.shape[1]},), got {a.shape}")
    lead = v.shape[:-1]
    n = v.shape[-1]
    f = jnp.broadcast_to(jnp.asarray(frequency_hz, grid.dtype), lead)
    i, t, ok = _bracket(f, grid)
    j = jnp.minimum(i + 1, grid.shape[0] - 1)

    def density(k, vk):  # Re(v* (R v)) per vertex (W), summing to W at grid frequency k
        return jnp.real(jnp.conj(vk) * (L[k] @ (jnp.conj(L[k]).T @ vk)))

    def one(args):
        vk, ik, jk, tk = args
        qa, qb = density(ik, vk), density(jk, vk)
        wa, wb = jnp.sum(qa), jnp.sum(qb)
        lin = (1 - tk) * wa + tk * wb
        scale = jnp.where(lin > 0, _loglog(wa, wb, tk) / jnp.where(lin > 0, lin, 1.0), 1.0)
        return scale * ((1 - tk) * qa + tk * qb)

    q = jax.lax.map(one, (v.reshape(-1, n), i.reshape(-1), j.reshape(-1), t.reshape(-1)))
    q = q.reshape(*lead, n) / a.reshape((1,) * len(lead) + (n,))
    return jnp.where(ok[..., None], q, jnp.nan)
