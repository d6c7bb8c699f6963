"""The kinds a body file chooses by name, as abstract classes: the finite element, the bearing
coupling, the rim coupling, the condensation method and the support of the reported modes.

Each kind is a class passed as an object (``Body.mesh.element`` is a :class:`~fem_prep.Hex20`,
not ``"hex20"``); the names of the body file are mapped to these objects in one place only, the
body-file reader :mod:`fem_prep.schema`.  The concrete kinds live beside the algorithm they
steer (``_elements``, ``_couplings``, ``_methods``, ``_prepare``); a new kind is one new subclass
there plus its name in :mod:`fem_prep.schema`.

A kind object prints as, and compares equal to, its body-file name (``Rigid() == "rigid"``), so
that summaries, reports and cache keys keep the names they had.
"""

from __future__ import annotations

import abc
from typing import ClassVar

__all__ = [
    "BearingCoupling",
    "CondensationMethod",
    "Element",
    "Kind",
    "RimCoupling",
    "RingSupport",
    "Support",
    "TetElement",
]


class Kind(abc.ABC):
    """A kind chosen by name in a body file; stateless, printed and compared by :attr:`name`."""

    name: ClassVar[str]
    """Its name in the body file (and in ``summary.json``)."""

    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"

    def __eq__(self, other: object) -> bool:
        return str(self) == str(other)

    def __hash__(self) -> int:
        return hash(self.name)


class Element(Kind):
    """The quadratic hexahedron of the body mesh (:class:`~fem_prep.Hex20`,
    :class:`~fem_prep.Hex27`).

    Attributes:
        intorder: the quadrature order of the stiffness and mass integrals.
    """

    intorder: ClassVar[int]

    @abc.abstractmethod
    def skfem_element(self):
        """The scalar scikit-fem element (``skfem.ElementHexS2()``, ``skfem.ElementHex2()``)."""

    @abc.abstractmethod
    def inner_nodes(self, faces: float, cells: float) -> float:
        """Nodes beyond the corners and edges of a meridian grid of ``cells`` cells and
        ``faces`` faces (radial-axial faces and the two kinds of faces across them), per
        circumferential division: none for the serendipity element, one per face and cell for the
        Lagrange element (the mesh-size estimate of :mod:`fem_prep.schema`)."""


class TetElement(Kind):
    """The tetrahedron of a housing mesh (:class:`~fem_prep.housing.Tet4`,
    :class:`~fem_prep.housing.Tet10`, on the straight-sided four-node geometry).

    Attributes:
        intorder: the quadrature order of the stiffness and mass integrals.
    """

    intorder: ClassVar[int]

    @abc.abstractmethod
    def skfem_element(self):
        """The scalar scikit-fem element (``skfem.ElementTetP1()``, ``skfem.ElementTetP2()``)."""


class BearingCoupling(Kind):
    """How a 6-DOF bearing node holds the bore nodes of its band (:class:`~fem_prep.Rigid`,
    :class:`~fem_prep.Averaging`; see :func:`fem_prep.couple_masters`)."""

    @abc.abstractmethod
    def rows(self, R, ring_dofs, first_column: int):
        """The eliminated rows of the transformation ``u_full = T q`` for one bearing.

        Args:
            R: ``(3 n_ring, 6)`` rigid kinematics of the band, ``u = R [u_B; theta_B]``.
            ring_dofs: ``(3 n_ring,)`` full DOF indices of the band nodes.
            first_column: the column key of the bearing's first DOF (``6 ib``).

        Returns:
            ``(rows, keys, values, eliminated)``: lists of arrays of full rows, column keys
            (``>= 0`` a new column, ``< 0`` the kept full DOF ``-1 - key``) and values, and the
            full DOFs this coupling eliminates.
        """


class RimCoupling(Kind):
    """How the rim masters hold the outer rim face (:class:`~fem_prep.Distributing`,
    :class:`~fem_prep.Nodal`; see :mod:`fem_prep._rim`)."""

    @abc.abstractmethod
    def masters(self, bm, rim, first_column: int):
        """The masters of one rim.

        Args:
            bm: the body mesh.
            rim: the rim's :class:`~fem_prep._couplings.RimMasters`.
            first_column: the column key of its first new master DOF.

        Returns:
            ``(rows, keys, values, positions, n_columns, eliminated)``: lists of the eliminated
            rows of ``T`` as :meth:`BearingCoupling.rows` (empty when the masters are FE nodes
            kept as such), the masters' positions ``(teeth, n_axial, 3)`` (m), the number of
            new columns and the full DOFs eliminated.
        """

    @abc.abstractmethod
    def master_dofs(self, rim, columns, full_to_red):
        """The reduced indices ``(teeth, n_axial, 3)`` of one rim's master DOFs, given the new
        columns this coupling made for it (``columns``) and the reduced index of each full DOF
        (``full_to_red``)."""

    @abc.abstractmethod
    def cache_revision(self) -> str:
        """What the cache key adds for this coupling's revision ("" when none)."""


class CondensationMethod(Kind):
    """A component-mode condensation (:class:`~fem_prep.Guyan`,
    :class:`~fem_prep.CraigBampton`, :class:`~fem_prep.Herting`; seed (2.3)-(2.5))."""

    @abc.abstractmethod
    def n_columns(self, n_modes: int) -> int:
        """The modal columns of the basis before the static correction."""

    @abc.abstractmethod
    def modal_block(self, part, H, n_modes: int):
        """Fill the modal columns of the basis ``H`` (``(n, n_b + n_columns)``, the constraint
        modes set) from the structure split ``part`` (:class:`fem_prep._condense.Partition`);
        returns ``(H, modes_hz)``, the frequencies of the modes kept (Hz)."""

    def early_modes(self, part, n_modes: int):
        """Modes that need only the interior blocks, computed before the ``(n, n_b + ...)``
        basis is allocated (so that the eigen-solver's workspace and the basis are not held
        together) and handed to :meth:`modal_block` as ``part.modes``; ``None`` (the default):
        :meth:`modal_block` computes its own."""

    @abc.abstractmethod
    def add_static_correction(self, part, H, modes_hz, f):
        """The basis and frequencies with the static correction vector of the load ``f``
        ``(n,)`` added (:func:`fem_prep.condense`); Guyan returns them unchanged."""


class Support(Kind):
    """How the body is held for the reported frequencies (:class:`~fem_prep.Bearings`,
    :class:`~fem_prep.Free`)."""

    @abc.abstractmethod
    def full_modes(self, cp, Kff, free, factor, n: int, progress: bool):
        """``(eigenvalues, mode shapes (n_red, n))`` of the coupled full model."""

    @abc.abstractmethod
    def held(self, bearing_dofs):
        """The condensed DOFs held for the condensed model's frequencies (indices)."""


class RingSupport(Kind):
    """How the housing holds a ring gear (:class:`~fem_prep.BoltedFlange`,
    :class:`~fem_prep.ElasticFoundation`, :class:`~fem_prep.FreeRing`; see :mod:`fem_prep._ring`).
    Unlike the other kinds, a support carries its parameters (bolt count, foundation
    stiffnesses): it compares by its fields."""

    @abc.abstractmethod
    def foundation(self, ring, bm):
        """The support's stiffness on the full DOFs of the mesh ``bm`` (N/m, sparse
        ``(n_dofs, n_dofs)``; zero for clamped seats)."""

    @abc.abstractmethod
    def clamped(self, ring, bm):
        """The full DOFs the support holds at zero (indices; none for a foundation)."""
