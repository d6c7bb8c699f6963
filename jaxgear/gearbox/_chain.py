"""A gearbox of stages in series as one torsional lumped model: each stage's torsional model (a
planetary stage's :class:`~jaxgear.TorsionalPlanetary`, a parallel pair's two rotations joined
by its mesh) in absolute rotations, the stages joined by the torsional stiffnesses of the shafts
that carry one stage's output member to the next stage's input member.

Coordinates: one rotation theta (rad) per member, every rotation positive in the same sense
about the common axis direction (a parallel pair's wheel and pinion included); M in kg m^2,
K in N m/rad. A planetary stage's model is :class:`~jaxgear.TorsionalPlanetary`'s, whose
coordinates are u = r theta (m) with r the member's ``base_radius`` (the carrier's: the planet
circle), so that its blocks here are R M R and R K R, R = diag(r). A parallel pair's mesh
deflection along its line of action is r_b1 theta_1 + r_b2 theta_2 (the two gears turn in
opposite senses), its mesh stiffness k: K = k [r_b1 r_b1, r_b1 r_b2; r_b1 r_b2, r_b2 r_b2].
A shaft of torsional stiffness k_t between coordinates i and j adds k_t (theta_i - theta_j)^2 / 2
to the strain energy.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import jax.scipy.linalg
import numpy as np
from jaxtyping import Array, Float

from .._planetary import Central, PlanetaryStage, TorsionalPlanetary
from .._util import as_float, check_instance

__all__ = [
    "AbstractGearboxStage",
    "GearboxModes",
    "GearboxTorsional",
    "PairGearboxStage",
    "PlanetaryGearboxStage",
    "gearbox_modes",
]


class AbstractGearboxStage(eqx.Module):
    """One stage of a gearbox in the torsional chain: its members' rotations, its matrices, and
    which of them are its input and output members."""

    @abc.abstractmethod
    def dof_names(self) -> tuple[str, ...]:
        """One name per rotation of the stage, in order."""

    @abc.abstractmethod
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K): kg m^2 and N m/rad, on the stage's rotations (rad)."""

    @abc.abstractmethod
    def ends(self) -> tuple[int, int]:
        """(input, output): the indices of the input and output members' rotations."""


class PlanetaryGearboxStage(AbstractGearboxStage):
    """A planetary stage in the chain (:class:`~jaxgear.TorsionalPlanetary`, Kahraman 1994:
    rotations of carrier, ring, sun and the N planets); ``input``/``output``: which central
    members (:class:`~jaxgear.Central`) the shafts join. A fixed member is held by its
    ``torsional_stiffness`` in ``stage``."""

    stage: PlanetaryStage
    input: Central = eqx.field(static=True)
    output: Central = eqx.field(static=True)

    def dof_names(self):
        return ("theta_c", "theta_r", "theta_s") + tuple(
            f"theta_{i + 1}" for i in range(self.stage.n_planets)
        )

    def matrices(self):
        model, st = TorsionalPlanetary(), self.stage
        r = jnp.concatenate(
            [
                jnp.stack([st.carrier.base_radius, st.ring.base_radius, st.sun.base_radius]),
                jnp.broadcast_to(st.planet.base_radius, (st.n_planets,)),
            ]
        )
        scale = r[:, None] * r[None, :]
        return scale * model.mass_matrix(st), scale * model.stiffness_matrix(st)

    def ends(self):
        # TorsionalPlanetary's order: u_c, u_r, u_s (Central's carrier, ring, sun)
        order = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}
        return order[self.input], order[self.output]


class PairGearboxStage(AbstractGearboxStage):
    """A parallel pair in the chain: pinion and wheel rotations (rad), their polar inertias
    (kg m^2, shape (2,)), base radii (m, shape (2,)) and the mean mesh stiffness along the line
    of action (N/m); ``input``: 0 when the pinion is driven by the previous stage, 1 the wheel
    (the other gear is the output)."""

    inertias: Float[Array, " 2"] = eqx.field(converter=as_float)
    base_radii: Float[Array, " 2"] = eqx.field(converter=as_float)
    mesh_stiffness: Float[Array, ""] = eqx.field(converter=as_float)
    input: int = eqx.field(static=True, default=1)

    def __check_init__(self):
        if self.input not in (0, 1):
            raise ValueError(f"input = {self.input!r}: out of range, allowed 0 (pinion), 1 (wheel)")

    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def matrices(self):
        r = self.base_radii
        return jnp.diag(self.inertias), self.mesh_stiffness * jnp.outer(r, r)

    def ends(self):
        return self.input, 1 - self.input


class GearboxTorsional(eqx.Module):
    """Stages in series (:class:`AbstractGearboxStage`), stage k's output member joined to stage
    k+1's input member by a shaft of torsional stiffness ``shaft_stiffnesses[k]`` (N m/rad,
    shape (n_stages - 1,)). The chain's coordinates are the stages' in order."""

    stages: tuple[AbstractGearboxStage, ...]
    shaft_stiffnesses: Float[Array, " n_shafts"] = eqx.field(converter=as_float)

    def __check_init__(self):
        if len(self.stages) < 1:
            raise ValueError("stages: empty, allowed at least one stage")
        if self.shaft_stiffnesses.shape != (len(self.stages) - 1,):
            raise ValueError(
                f"shaft_stiffnesses: shape {self.shaft_stiffnesses.shape}, allowed "
                f"({len(self.stages) - 1},) (one per pair of consecutive stages)"
            )

    def offsets(self) -> tuple[int, ...]:
        """Where each stage's rotations start in the chain's coordinates."""
        out, n = [], 0
        for s in self.stages:
            out.append(n)
            n += len(s.dof_names())
        return tuple(out)

    def dof_names(self) -> tuple[str, ...]:
        """``"<k>:<name>"`` per coordinate, k the stage's index from 1."""
        return tuple(f"{k + 1}:{n}" for k, s in enumerate(self.stages) for n in s.dof_names())

    def stage_of_dof(self) -> tuple[int, ...]:
        """Each coordinate's stage index (from 0)."""
        return tuple(k for k, s in enumerate(self.stages) for _ in s.dof_names())

    @eqx.filter_jit
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K) of the chain: kg m^2, N m/rad."""
        blocks = [s.matrices() for s in self.stages]
        mass = jax.scipy.linalg.block_diag(*[m for m, _ in blocks])
        stiff = jax.scipy.linalg.block_diag(*[k for _, k in blocks])
        # the shafts: twist b theta, b = e_out(k) - e_in(k + 1), strain energy k_t (b theta)^2 / 2
        offsets = self.offsets()
        b = np.zeros((len(self.stages) - 1, mass.shape[0]))
        for j in range(len(self.stages) - 1):
            b[j, offsets[j] + self.stages[j].ends()[1]] = 1.0
            b[j, offsets[j + 1] + self.stages[j + 1].ends()[0]] = -1.0
        b = jnp.asarray(b, dtype=mass.dtype)
        stiff = stiff + b.T @ (self.shaft_stiffnesses[:, None] * b)
        return mass, stiff


class GearboxModes(eqx.Module):
    """The chain's natural modes: ``frequencies`` (Hz, ascending, shape (n,)), ``shapes``
    (rad, (n, n), column j mass-normalised: phi^T M phi = I) and ``stage_energy`` ((n_stages, n):
    each mode's kinetic energy share per stage, columns summing to 1)."""

    frequencies: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    stage_energy: Float[Array, "s n"]


@eqx.filter_jit
def gearbox_modes(chain: GearboxTorsional) -> GearboxModes:
    """The undamped natural modes of the chain, ``K phi = omega^2 M phi`` (symmetric form by
    the Cholesky factor of M, ``jnp.linalg.eigh``); a free chain (no member held) has one
    rigid-body mode at 0 Hz.

    Raises:
        ValueError: ``chain`` not a :class:`GearboxTorsional` (one line)."""
    check_instance("chain", chain, GearboxTorsional, "a jaxgear.GearboxTorsional",
                   "gearbox_modes")
    m, k = chain.matrices()
    low = jnp.linalg.cholesky(m)
    a = jnp.linalg.solve(low, jnp.linalg.solve(low, k).T)
    lam, vec = jnp.linalg.eigh(0.5 * (a + a.T))
    shapes = jnp.linalg.solve(low.T, vec)
    energy = shapes * (m @ shapes)  # each coordinate's share (M diagonal per stage block)
    owner = np.asarray(chain.stage_of_dof())  # static: the indicator of each stage's rotations
    belongs = jnp.asarray(owner[None, :] == np.arange(len(chain.stages))[:, None], energy.dtype)
    per_stage = belongs @ energy
    per_stage = per_stage / per_stage.sum(axis=0, keepdims=True)
    return GearboxModes(jnp.sqrt(jnp.clip(lam, 0.0)) / (2.0 * jnp.pi), shapes, per_stage)
