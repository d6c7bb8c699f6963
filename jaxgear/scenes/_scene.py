"""Linear structures that the contact law acts on, through structure vectors (seed (2.9)).

A scene has n generalised coordinates X. The approach of cell c (flank-normal, m) is V_c·X, and
the contact force p_c l_c on the cell acts on the structure as −p_c l_c V_c. Each scene provides:

* ``stiffness()``: the structure's own stiffness K_s, shape (n, n);
* ``external_load(torque)``: generalised external forces F, shape (n,), for pinion torque T;
* ``cell_vectors(cells)``: V for every cell, shape (n_lines, n_slices, n);
* ``te_vector()``: u with u·X the flank-normal rigid-body approach of the mesh (the transmission
  error before the ``− max e`` and 1/cos β_b of docs/design.md, "Modifications, initial
  separation and TE");
* ``static_contact(cells, delta0, torque, speed, law)``: the static contact at one mesh position.
  Scenes of a few coordinates solve it in coordinates (the default here); a scene of condensed
  bodies overrides it with the cell space (:class:`jaxgear.scenes.HybridPair`).

Later scenes (shafts, bearings, condensed bodies) plug into the same solver by providing these.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow, Cells
from .._contact import ContactLaw, ContactSolution, solve_contact
from .._util import as_float

__all__ = ["DynamicScene", "Grounded", "Scene", "grounded"]


class Scene(eqx.Module):
    """Abstract linear structure seen by the contact law."""

    @abc.abstractmethod
    def stiffness(self) -> Float[Array, "n n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def external_load(self, torque: Float[Array, ""]) -> Float[Array, " n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def cell_vectors(self, cells: Cells) -> Float[Array, "n_lines n_slices n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def te_vector(self) -> Float[Array, " n"]:
        """See the module docstring."""

    def static_contact(
        self, cells: Cells, delta0, torque, speed, law: ContactLaw
    ) -> tuple[ContactSolution, Float[Array, " n"], Float[Array, ""]]:
        """The static contact at one mesh position, in coordinates (:func:`jaxgear.solve_contact`
        on K_s X + Σ P V = F).

        Args:
            cells: the cells at the position (n_lines, n_slices). delta0: their initial
                separation δ0 (m), same shape. torque: pinion torque (N·m). speed: pinion
                speed (rad/s), unused here (no member of this scene carries a centrifugal
                load). law: the contact law.

        Returns:
            (the contact solution, X (n,), u·X (m)).
        """
        r = CellRow.of(cells, self.cell_vectors(cells), delta0)
        K, F = self.stiffness(), self.external_load(torque)
        sol = solve_contact(K, F, r.V, r.k, r.length, r.delta0, r.mask, law)
        return sol, sol.x, self.te_vector() @ sol.x


class DynamicScene(Scene):
    """Abstract scene with inertia: adds :meth:`mass`, :meth:`rigid_modes` and the named parts of
    the structure stiffness (for the strain-energy shares of the modal analysis)."""

    @abc.abstractmethod
    def mass(self) -> Float[Array, "n n"]:
        """Mass matrix M, shape (n, n) (kg, kg·m², per coordinate)."""

    def reaction_matrix(self) -> Float[Array, "r n"]:
        """Rows R with R X the support (bearing) force components (N); none by default."""
        M = self.mass()
        return jnp.zeros((0, M.shape[0]), M.dtype)

    @abc.abstractmethod
    def rigid_modes(self) -> Float[Array, "n r"]:
        """Rigid-body modes r (columns, r may be 0) with V·r = 0 and F·r = 0."""

    @abc.abstractmethod
    def stiffness_parts(self) -> dict[str, Float[Array, "n n"]]:
        """Named structure stiffness matrices summing to :meth:`stiffness`."""


class Grounded(Scene):
    """A scene with some coordinates tied to the ground by a stiff spring (for statics).

    Dynamic scenes keep rigid-body modes (the torsional chain turns freely) that make their
    stiffness singular in a quasi-static solve. Grounding the output rotation (the load) removes
    the mode; in a statically determinate torsional chain it changes neither the transmission error
    nor the bearing loads.

    Attributes:
        base: the scene. dofs: grounded coordinate indices (static).
        stiffness_value: spring stiffness in the units of those coordinates (default 1e3 times
            the largest diagonal term of the base stiffness).
    """

    base: Scene
    stiffness_value: Float[Array, ""] = eqx.field(converter=as_float)
    dofs: tuple = eqx.field(static=True)

    @property
    def mesh(self):
        return self.base.mesh

    def stiffness(self):
        K = self.base.stiffness()
        idx = jnp.asarray(self.dofs)
        return K.at[idx, idx].add(self.stiffness_value)

    def external_load(self, torque):
        return self.base.external_load(torque)

    def cell_vectors(self, cells):
        return self.base.cell_vectors(cells)

    def te_vector(self):
        return self.base.te_vector()


def grounded(scene: Scene, dofs, factor: float = 1e3) -> Grounded:
    """Ground ``dofs`` of ``scene`` with springs ``factor`` × the largest diagonal stiffness."""
    k = float(jnp.max(jnp.abs(jnp.diag(scene.stiffness()))))
    return Grounded(scene, factor * max(k, 1.0), tuple(int(d) for d in dofs))
