"""The stage contract (docs/architecture.md, "One stage contract"): what a model of one stage
(a parallel pair, a planetary stage, a compound stage) gives a gearbox that joins several of
them by shafts in one coupled run (:class:`jaxgear.gearbox.GearboxTorsional`,
:class:`jaxgear.gearbox.GearboxModel`).

A stage is written once, on this engine-side contract, and a model that runs alone on the
dynamics contract (:class:`~jaxgear.dynamics.AbstractDynamicModel`) is a stage by subclassing
this class too: :class:`jaxgear.planetary.PlanetaryModel` with its ``input`` and ``output``
members is one, so the object that :func:`~jaxgear.dynamics.simulate` runs alone is the object
a gearbox takes. Whether a kind is a stage is declared by the class (an ``isinstance`` of
:class:`AbstractStage`), never probed; an instance that cannot stand in a gearbox (a planetary
model without its members' roles) refuses in one line in :meth:`AbstractStage.check_stage`.

Conventions: a stage's coordinates are rotations (rad) and translations (m) in its own frame
(a planetary stage's: its carrier's); mass in kg or kg m^2, stiffness in N/m, N/rad or N m/rad
per coordinate pair; a stage's mesh travel x (m) drives its contact cells; torques in N m,
speeds in rad/s (the fixed frame), forces in N (compression positive).
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow
from .._util import as_float
from ..scenes import HousingMount
from ._model import cell_stiffness

__all__ = ["AbstractStage", "mean_cell_stiffness"]


def mean_cell_stiffness(cell_row, period, positions: int) -> Float[Array, "n n"]:
    """K̄_m of a stage's meshes: their cells' stiffness Σ k l V Vᵀ (:func:`cell_stiffness`)
    averaged over ``positions`` mid-points of the period ``period`` (m of mesh travel), the
    cells from ``cell_row`` (a function of the travel, (n, n) on the stage's coordinates; pass
    the stage on the theoretical path, :func:`jaxgear.on_the_path`: beyond it a corner's cell
    carries load only under deflection)."""
    x = period * (jnp.arange(positions) + 0.5) / positions
    rows = jax.vmap(cell_row)(x)
    kl = jnp.where(rows.mask, rows.k * rows.length, 0.0)
    return cell_stiffness(rows.V, kl) / positions


class AbstractStage(eqx.Module):
    """One stage of a gearbox: its coordinates, its matrices and contact cells, which of its
    members the shafts join, its kinematics. The one stage contract of the package (the
    gearbox's stage kinds and :class:`jaxgear.planetary.PlanetaryModel` satisfy it).

    Abstract: :meth:`dof_names`, :meth:`matrices`, :meth:`ends` (the torsional chain's view:
    one rotation per member) and :meth:`dynamic_parts`, :meth:`cell_row`,
    :meth:`mesh_forces`, :meth:`mesh_names`, :meth:`mesh_period`, :meth:`kinematics` (the
    coupled model). With defaults: :meth:`coordinates` and :meth:`coordinate_ends` (a
    torsional stage's: the chain's), :meth:`on_flanks`, :meth:`excited`,
    :meth:`carrier_speed`, :meth:`speed_terms` (a stage in the fixed frame),
    :meth:`mount` (a stage on the ground; :meth:`housing` and :meth:`housing_seats` read it)
    and :meth:`check_stage`
    (every instance stands in a gearbox).

    ``takes_housing`` (a class attribute, False here): whether the kind's coordinates can end
    with a flexible housing's that a gearbox shares (:meth:`mount`);
    True on :class:`~jaxgear.planetary.PlanetaryModel` and
    :class:`~jaxgear.gearbox.LumpedPairGearboxStage`.
    """

    takes_housing: ClassVar[bool] = False

    # -- the torsional chain's view ---------------------------------------------------------

    @abc.abstractmethod
    def dof_names(self) -> tuple[str, ...]:
        """One name per rotation of the stage in the torsional chain, in order."""

    @abc.abstractmethod
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K): kg m^2 and N m/rad, on the stage's rotations (rad)."""

    @abc.abstractmethod
    def ends(self) -> tuple[int, int]:
        """(input, output): the indices of the input and output members' rotations."""

    # -- the coupled dynamic model ------------------------------------------------------------

    def check_stage(self, where: str) -> None:
        """Refuse (``ValueError``, one line naming ``where``) an instance that cannot stand in
        a gearbox; the default: every instance of a stage kind can."""

    def coordinates(self) -> tuple[str, ...]:
        """The stage's coordinates in the coupled dynamic model (rad for a rotation, m for a
        translation); default: :meth:`dof_names` (a torsional stage)."""
        return self.dof_names()

    def coordinate_ends(self) -> tuple[int, int]:
        """:meth:`ends` in :meth:`coordinates` (the rotations the shafts join)."""
        return self.ends()

    @abc.abstractmethod
    def dynamic_parts(self, positions: int):
        """(M, K_s, K̄_m, F): mass, structure stiffness without the meshes, the meshes' cell
        stiffness averaged over ``positions`` mid-points of a mesh period, and the stage's own
        constant load (pin errors; N or N m), on :meth:`coordinates`."""

    @abc.abstractmethod
    def cell_row(self, x) -> CellRow:
        """The stage's contact cells at its mesh travel ``x`` (m) on :meth:`coordinates`
        (every mesh's, in :meth:`mesh_names`' order)."""

    def on_flanks(self, sign) -> AbstractStage:
        """The stage with its cells placed for the flanks the load is on: ``sign`` (traced,
        +1 or -1) the sign of its mesh deflections under the static load (-1: the other flanks
        than its cells' own). The default: the same cells (a pair's two flanks alike; the
        coupled model flips their rows' sign)."""
        return self

    @abc.abstractmethod
    def mesh_forces(self, forces) -> Float[Array, "... m"]:
        """Each mesh's transverse force (N, compression positive), (..., m), from the cell
        forces (N, (..., c))."""

    @abc.abstractmethod
    def mesh_names(self) -> tuple[str, ...]:
        """One name per mesh."""

    @abc.abstractmethod
    def mesh_period(self) -> Float[Array, ""]:
        """p_b (m): the mesh travel of one mesh period."""

    @abc.abstractmethod
    def kinematics(self, input_speed, input_torque):
        """(output speed (rad/s), output torque (N m), mesh travel speed v (m/s), each mesh's
        static transverse force (N, (m,))) at the input member's speed (rad/s) and torque
        (N m, its magnitude carried; the stage's drive flanks are the ones it loads)."""

    def excited(self) -> bool:
        """Whether the stage's meshes vary along the mesh travel (contact cells): a stage of
        constant springs sets no time scale of a run."""
        return True

    def carrier_speed(self, input_speed):
        """The speed (rad/s) of the frame the stage's coordinates are written in (a planetary
        stage: its carrier's) at its input member's ``input_speed``; default 0 (the fixed
        frame: a parallel pair)."""
        return 0.0 * as_float(input_speed)

    def speed_terms(self, carrier_speed):
        """(C_Omega, K_Omega): the rotating frame's damping and stiffness terms (Coriolis,
        centripetal) on :meth:`coordinates` at the stage's carrier speed (rad/s); zero for a
        torsional stage."""
        n = len(self.coordinates())
        z = jnp.zeros((n, n))
        return z, z

    def mount(self) -> HousingMount | None:
        """The :class:`~jaxgear.scenes.HousingMount` whose housing's h coordinates end
        :meth:`coordinates` (its seats' 6 each, then its modal ones) and whose joints seat the
        stage's bearings or members, which a gearbox-level housing
        (:attr:`jaxgear.gearbox.GearboxTorsional.housing`) shares with the other stages; None
        (the default): the stage stands on the ground."""
        return None

    def housing(self) -> tuple[Float[Array, "h h"], Float[Array, "h h"]] | None:
        """(K_h, M_h) of :meth:`mount`'s housing, or None: the stage on the ground."""
        mount = self.mount()
        return None if mount is None else (mount.K, mount.M)

    def housing_seats(self) -> tuple[int, ...]:
        """The seats (indices) :meth:`mount`'s joints use, in ascending order; () for a stage
        on the ground."""
        mount = self.mount()
        return () if mount is None else mount.seats()
