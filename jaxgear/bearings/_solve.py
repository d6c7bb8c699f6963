"""The inverse of a bearing's load: the ring displacement that carries a given load.

The load f(d) of every kind is the gradient of its contact energy U(d) (a sum of
K_n/(n + 1) max(δ_j, 0)^(n + 1) over its elements), and each approach δ_j is convex in d (affine
for rollers, the length of an affine vector less a constant for balls), so the displacement
carrying a load F is the minimum of the convex Π(d) = U(d) − F·d. It is found by optimistix's
BFGS on Π (global, with its line search), then polished by optimistix's Newton root find on
∇Π = f(d) − F (the Jacobian the stiffness, solved by lineax), in scaled units: translations by
the approach δ_ref = (|F| / (Z K_n))^(1/n) + |P_d|/2 and tilts by it over the pitch radius.
A DOF the bearing does not carry (:meth:`~AbstractRollingBearing.carried`) is held at 0, and a
small regularisation (10⁻¹² of the scaled curvature) makes a free play (clearance without load)
choose its centre. Gradients of the solution (with respect to the load or the geometry) are
optimistix's implicit ones.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from jaxtyping import Array, Float, Int

from .._util import check_instance, check_integer, check_real, is_traced
from ._kinds import AbstractRollingBearing

__all__ = ["BearingState", "solve_displacement"]

#: the regularisation of a free play, relative to the scaled curvature
REGULARISATION = 1e-12


class BearingState(eqx.Module):
    """A bearing at an operating point (:func:`solve_displacement`).

    Attributes:
        displacement: d = (δ_x, δ_y, δ_z, γ_x, γ_y) (m, rad), (5,).
        load: f(d) (N, N·m), (5,): the carried load.
        stiffness: K = ∂f/∂d at d, (5, 5).
        residual: max |f(d) − F| over the force rows and the moment rows over the pitch
            radius, relative to the largest of them in F (-).
        steps: BFGS iterations and Newton iterations, (2,).
    """

    displacement: Float[Array, " 5"]
    load: Float[Array, " 5"]
    stiffness: Float[Array, "5 5"]
    residual: Float[Array, ""]
    steps: Int[Array, " 2"]


def _scales(bearing, F):
    """(δ_ref (m), lever r (m), F_ref (N)) of the scaled problem."""
    if bearing.rolling_elements:
        r = 0.5 * bearing.pitch_diameter
    else:
        r = jnp.asarray(1.0)
    Fs = jnp.concatenate([F[:3], F[3:] / r])
    F_ref = jnp.maximum(jnp.max(jnp.abs(Fs)), 1e-30)
    if bearing.rolling_elements:
        n = bearing.contact_exponent
        d_ref = (F_ref / (bearing.elements * bearing.hertz_constant)) ** (1.0 / n)
        d_ref = d_ref + 0.5 * jnp.abs(bearing.clearance) + 1e-12 * bearing.element_diameter
    else:
        k = jnp.asarray([bearing.radial, bearing.axial, bearing.tilt / r**2])
        d_ref = F_ref / jnp.maximum(jnp.max(k), 1e-30)
    return d_ref, r, F_ref


@eqx.filter_jit
def _solve(bearing, F, max_steps, carried):
    d_ref, r, F_ref = _scales(bearing, F)
    unit = jnp.asarray([1.0, 1.0, 1.0, 1.0 / r, 1.0 / r]) * d_ref
    held = 1.0 - jnp.asarray(carried, float)

    def to_d(y):
        return y * unit * (1.0 - held)

    def energy(y, _):
        d = to_d(y)
        pi = (bearing.potential(d) - F @ d) / (F_ref * d_ref)
        return pi + 0.5 * jnp.sum(held * y**2) + 0.5 * REGULARISATION * jnp.sum(y**2)

    y0 = jnp.where(held > 0, 0.0, jnp.concatenate([F[:3], F[3:] / r]) / F_ref)
    first = optx.minimise(energy, optx.BFGS(rtol=1e-8, atol=1e-8), y0, max_steps=max_steps,
                          throw=False)
    gradient = jax.grad(energy)
    polish = optx.root_find(lambda y, a: gradient(y, a), optx.Newton(rtol=1e-12, atol=1e-12),
                            first.value, max_steps=32, throw=False)
    d = to_d(polish.value)
    f = bearing.load(d)
    err = jnp.concatenate([f[:3] - F[:3], (f[3:] - F[3:]) / r]) * (1.0 - held)
    steps = jnp.stack([first.stats["num_steps"], polish.stats["num_steps"]])
    return BearingState(d, f, bearing.stiffness(d), jnp.max(jnp.abs(err)) / F_ref, steps)


def solve_displacement(bearing: AbstractRollingBearing, load, *, max_steps: int = 256
                       ) -> BearingState:
    """The ring displacement d at which ``bearing`` carries ``load`` (module docstring).

    Args:
        bearing: an :class:`AbstractRollingBearing` kind.
        load: F = (F_x, F_y, F_z, M_x, M_y) (N, N·m), (5,): the load the shaft puts on the
            bearing (the inner ring's push on the outer ring).
        max_steps: BFGS iterations at most (int >= 1).

    Returns:
        :class:`BearingState` at the solution (its ``residual`` says how well it converged: about
        1e-12 when it did).

    Raises:
        ValueError: a load on a DOF the bearing does not carry (an axial load on a cylindrical
            roller bearing, a moment on a spring without tilt stiffness); a single-row angular
            contact or tapered bearing loaded with F_z < F_r tan α (it needs that much axial
            load to carry its radial load: a partner bearing supplies it); one line each.
    """
    check_instance("bearing", bearing, AbstractRollingBearing,
                   "a jaxgear.bearings kind (DeepGrooveBall, ..., LinearSpring)",
                   where="solve_displacement")
    check_real("load", load, "N, N·m", shape=(5,), shape_text="(5,): F_x, F_y, F_z, M_x, M_y",
               where="solve_displacement")
    check_integer("solve_displacement: max_steps", max_steps, 1)
    F = jnp.asarray(load, dtype=float)
    carried = bearing.carried()
    if not is_traced(load):
        f = np.asarray(load, dtype=float)
        names = ("F_x", "F_y", "F_z", "M_x", "M_y")
        for i, (c, name) in enumerate(zip(carried, names, strict=True)):
            if not c and f[i] != 0:
                raise ValueError(
                    f"solve_displacement: load[{i}] ({name}) = {f[i]:g} on a DOF "
                    f"{type(bearing).__name__} does not carry: allowed 0"
                )
        if bearing.axial_load == "positive":
            alpha = float(np.asarray(bearing.nominal_angle))
            least = float(np.hypot(f[0], f[1])) * np.tan(alpha)
            if not f[2] > least or f[2] <= 0:
                raise ValueError(
                    f"solve_displacement: load[2] (F_z) = {f[2]:g} N on a single-row "
                    f"{type(bearing).__name__}: allowed > F_r tan(alpha) = {least:g} N (and "
                    "> 0: it carries an axial load one way; a partner bearing supplies it)"
                )
    return _solve(bearing, F, int(max_steps), carried)
