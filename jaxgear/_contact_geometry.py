"""Where the teeth can touch: the kinds of contact geometry of a mesh model.

:class:`TheoreticalPath` keeps contact on the theoretical path of contact [0, g_α] (the line of
action between the tip circles; the seed's model). :class:`BeyondPath` adds the contact beyond
the theoretical path that loaded, deflected teeth make at their tip corners: premature
engagement before its start and late disengagement after its end (docs/extended-contact.md).
A :class:`~jaxgear.MeshModel` holds one (``contact_geometry``, static); what the code used to
choose between on a flag, the kind's methods do: the cells' extent, the corner's gap and where
its force acts, the deviations it reads, the structure vectors' corner terms and the rigid
drive rotation they leave out, the overrun check and the layout of contact lines.

The methods take the mesh model (``mesh``) they serve: the tables beyond the path
(``extension_span``, ``extension_gap``, ``extension_corner``) are the mesh model's arrays, so
a kind holds no data and is hashable (a static field).
"""

from __future__ import annotations

import abc
import dataclasses
from collections.abc import Callable
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ._extended import corner_table, extension_table, line_range

__all__ = ["AbstractContactGeometry", "BeyondPath", "TheoreticalPath"]


@dataclasses.dataclass(frozen=True)
class AbstractContactGeometry(abc.ABC):
    """Where a mesh model's teeth can touch (a kind passed as an object; its subclasses
    :class:`TheoreticalPath`, :class:`BeyondPath`).

    Class attributes:
        reaches_beyond_path: whether cells lie beyond the theoretical path (what a presenter
            asks to draw where contact really starts and ends; the summary's
            ``extended_contact``).
        description: the words a rating sheet gives the contact model.
    """

    reaches_beyond_path: ClassVar[bool]
    description: ClassVar[str]

    @abc.abstractmethod
    def tables(self, pair, coast: bool) -> tuple:
        """The tables of :meth:`jaxgear.MeshModel.from_pair` for ``pair``: ``(span, gap,
        corner)``, (S_a, S_r) (m), the corner gaps (2, n_ext) (m) and the corner table (2, 4,
        n_ext) (:func:`jaxgear._extended.corner_table`). ``coast``: the model lays out the coast
        flanks too.

        Raises:
            ValueError: a kind that cannot serve coast flanks, with ``coast``."""

    @abc.abstractmethod
    def line_span(self, mesh) -> tuple:
        """(S_a, S_r) (m): how far the contact lines laid out must reach beyond the path's
        start and end.

        Raises:
            ValueError: a mesh model built without this kind's tables."""

    @abc.abstractmethod
    def cell_range(self, mesh) -> tuple:
        """(lo, hi) (m): the base-plane coordinates s of the cells on the flanks, lo <= s <=
        hi."""

    @abc.abstractmethod
    def corner_gap(self, mesh, s):
        """The flank-normal tip-corner gap (m) at base-plane coordinates ``s`` (m), shaped like
        ``s`` (:meth:`jaxgear.MeshModel.extension_separation`)."""

    @abc.abstractmethod
    def corner(self, mesh, s) -> tuple:
        """Where the force of a cell at ``s`` (m) acts: ``(lever_driving, lever_driven, eps,
        o_t, o_v)``, arrays shaped like ``s`` (:meth:`jaxgear.MeshModel.corner`)."""

    @abc.abstractmethod
    def lever_ratios(self, mesh, s) -> tuple:
        """(driving, driven): each gear's lever ratio at ``s`` (-), what its rotation's entry of
        a cell's structure vector is multiplied by: arrays shaped like ``s``, or 1.0 where
        every cell acts on the base radii."""

    @abc.abstractmethod
    def deviation_cells(self, mesh, cells):
        """``cells`` (:class:`~jaxgear.Cells`) placed where the flank deviations are read: a
        corner cell beyond the path reads its path end's."""

    @abc.abstractmethod
    def with_corner_gap(self, mesh, cells, delta0):
        """The initial separations ``delta0`` (m, (L, N)) of ``cells`` with the corner's gap
        added on the flanks."""

    @abc.abstractmethod
    def overrun(self, mesh, cells, gap):
        """Whether the solved approach would close the corner gap past the far end of the cells
        beyond the path (a boolean array; :meth:`jaxgear.MeshModel.extension_overrun`)."""

    @abc.abstractmethod
    def member_lines(self, gear_mesh, members: tuple, cells, line: dict) -> tuple:
        """``(points, (line_driving, line_driven))``: where the cells of ``gear_mesh`` (a
        :class:`~jaxgear.scenes.GearMesh`) act for each of its two members, the ``line``
        (:meth:`~jaxgear.scenes.GearMesh.line`) each member's window takes."""

    @abc.abstractmethod
    def beyond_path_vectors(self, mesh, s, V, free: Callable, added: Callable | None = None):
        """Structure vectors ``V`` (..., w) of cells at ``s`` (m) with the corner's terms:
        ``added()`` (the corner cells' geometry, same shape) added, then, on the cells beyond
        the path, ``free(V)`` (their part along the free drive rotations left out)."""

    @abc.abstractmethod
    def on_path(self, mesh):
        """``mesh`` with its cells beyond the path masked off, the shapes kept (the means over
        the flanks at no load, :func:`jaxgear.on_the_path`): ``mesh`` itself where it has
        none."""


@dataclasses.dataclass(frozen=True)
class TheoreticalPath(AbstractContactGeometry):
    """Contact on the theoretical path of contact only, s ∈ [0, g_α] (the seed's model):
    every cell acts on the line of action with the base radii."""

    reaches_beyond_path: ClassVar[bool] = False
    description: ClassVar[str] = "theoretical path of contact (contact on the line of action only)"

    def tables(self, pair, coast: bool) -> tuple:
        corner = np.zeros((2, 4, 2))
        corner[:, 0] = 1.0
        return (0.0, 0.0), np.zeros((2, 2)), corner

    def line_span(self, mesh) -> tuple:
        return (0.0, 0.0)

    def cell_range(self, mesh) -> tuple:
        return 0.0, mesh.path_of_contact

    def corner_gap(self, mesh, s):
        return jnp.zeros_like(s)

    def corner(self, mesh, s) -> tuple:
        one, zero = jnp.ones_like(s), jnp.zeros_like(s)
        return one, one, zero, zero, zero

    def lever_ratios(self, mesh, s) -> tuple:
        return 1.0, 1.0

    def deviation_cells(self, mesh, cells):
        return cells

    def with_corner_gap(self, mesh, cells, delta0):
        return delta0

    def overrun(self, mesh, cells, gap):
        return jnp.asarray(False)

    def member_lines(self, gear_mesh, members: tuple, cells, line: dict) -> tuple:
        return gear_mesh.points(cells), (line, line)

    def beyond_path_vectors(self, mesh, s, V, free: Callable, added: Callable | None = None):
        return V

    def on_path(self, mesh):
        return mesh


@dataclasses.dataclass(frozen=True)
class BeyondPath(AbstractContactGeometry):
    """Contact beyond the theoretical path of contact as well: cells before its start
    (s ∈ [−S_a, 0), premature engagement, the driven gear's tip corner on the driving flank)
    and after its end (s ∈ (g_α, g_α + S_r], late disengagement, the driving gear's tip
    corner on the driven flank), each holding the corner's gap, which the deflection closes
    (:class:`jaxgear.CornerContact`; the extension's reach :func:`jaxgear.extension_table`;
    docs/extended-contact.md). Not modelled with backlash (coast flanks)."""

    reaches_beyond_path: ClassVar[bool] = True
    description: ClassVar[str] = "extended path of contact (off-line contact at the tip corners)"

    def tables(self, pair, coast: bool) -> tuple:
        if coast:
            raise ValueError(
                "mesh.extended_contact with backlash (coast flanks) is not modelled: set "
                "mesh.extended_contact = false or drop the tooth thickness allowances"
            )
        span, gap = extension_table(pair)
        return span, gap, corner_table(pair, span, gap.shape[1])

    def line_span(self, mesh) -> tuple:
        span = tuple(float(x) for x in np.asarray(mesh.extension_span))
        if not max(span) > 0.0:
            raise ValueError(
                "contact beyond the path needs the gap table: build the mesh model with "
                "MeshModel.from_pair(..., contact_geometry=BeyondPath())"
            )
        return span

    def cell_range(self, mesh) -> tuple:
        return -mesh.extension_span[0], mesh.path_of_contact + mesh.extension_span[1]

    def corner_gap(self, mesh, s):
        beyond, _, values = mesh._beyond_path(s)
        return jnp.where(beyond, values[..., 0], 0.0) * jnp.cos(mesh.base_helix_angle)

    def corner(self, mesh, s) -> tuple:
        one = jnp.ones_like(s)
        beyond, after, values = mesh._beyond_path(s)
        on_path = jnp.asarray([1.0, 0.0, 0.0, 0.0], values.dtype)
        lam, eps, o_t, o_v = jnp.moveaxis(
            jnp.where(beyond[..., None], values[..., 1:], on_path), -1, 0
        )
        return jnp.where(after, lam, one), jnp.where(beyond & ~after, lam, one), eps, o_t, o_v

    def lever_ratios(self, mesh, s) -> tuple:
        return self.corner(mesh, s)[:2]

    def deviation_cells(self, mesh, cells):
        return eqx.tree_at(lambda c: c.s, cells, jnp.clip(cells.s, 0.0, mesh.path_of_contact))

    def with_corner_gap(self, mesh, cells, delta0):
        return delta0 + jnp.where(cells.mask, self.corner_gap(mesh, cells.s), 0.0)

    def overrun(self, mesh, cells, gap):
        s = cells.s
        lead = cells.mask & (s < 0.0)
        trail = cells.mask & (s > mesh.path_of_contact)
        end = mesh.extension_gap[:, -1] * jnp.cos(mesh.base_helix_angle)
        reach = gap + self.corner_gap(mesh, s)
        return jnp.any(lead & (reach > end[0])) | jnp.any(trail & (reach > end[1]))

    def member_lines(self, gear_mesh, members: tuple, cells, line: dict) -> tuple:
        # each member sees the corner's point, its turned normal and its own lever ratio
        # (docs/extended-contact.md, "Where it acts")
        P, n, levers = gear_mesh.corner_contact(members, cells)
        return P, tuple({**line, "cell_normal": n, "lever": lever} for lever in levers)

    def beyond_path_vectors(self, mesh, s, V, free: Callable, added: Callable | None = None):
        if added is not None:
            V = V + added()
        beyond = (s < 0.0) | (s > mesh.path_of_contact)
        return jnp.where(beyond[..., None], free(V), V)

    def on_path(self, mesh):
        return dataclasses.replace(mesh, contact_geometry=TheoreticalPath())


def rolling_lever(lever_driving, lever_driven, weights):
    """c = (λ1 w1 + λ2 w2)/(w1 + w2) (-): the factor on both members' rotation entries of a
    corner cell in the rows a solver uses, in place of each member's own lever ratio λ (1 on
    the path, where c = 1 too), shaped like the lever ratios.

    ``lever_driving``, ``lever_driven``: the two gears' lever ratios λ
    (:meth:`AbstractContactGeometry.lever_ratios`, :meth:`jaxgear.MeshModel.corner`: the tip
    owner's λ_T < 1 beyond the path, the flank owner's 1). ``weights``: (w1, w2), how the
    part taken off is shared between the two members: (r_b1, r_b2), the pair's base radii in
    the sense its coordinates count the rotations (a planetary stage's meshes, the ring's
    negative: taken off equally from the two rotation angles, so that the stage's rigid
    rotation still moves no gap), or (1, 0), the driving gear's own lever kept (the driven
    gear held: a pair whose gear sits on its output shaft, as :class:`~jaxgear.scenes.RigidMesh`
    and the plane-strain FE reference hold it).

    The exact gap derivative (r_bF for the flank owner, λ r_bT for the tip owner) has a part
    along the pair's rolling (both members turning at the conjugate ratio, centres fixed:
    dgap/ds = 1 − λ per unit roll); c (r_b1, ±r_b2) is that derivative less this part, so that
    the rolling moves no corner gap, as on the path. The cells' positions follow the nominal
    motion, so a rolling held only by a soft support (a condensed ring turning mm on its
    housing, a pair's output shaft) is a phase the cells do not follow and must not close a
    corner (docs/extended-contact.md, "The pair's rolling"). The price: the two members'
    torques from a corner cell keep the line of action's ratio r_b2/r_b1 (the corner's broken
    torque ratio is dropped; with (1, 0) the driving gear's balance stays exact)."""
    w1, w2 = weights
    return (lever_driving * w1 + lever_driven * w2) / (w1 + w2)


def contact_geometry_of(extended: bool) -> AbstractContactGeometry:
    """The kind a boolean ``extended_contact`` stood for (the deprecated spelling)."""
    return BeyondPath() if extended else TheoreticalPath()


def line_layout(mesh, geometry: AbstractContactGeometry) -> tuple:
    """(n_lines, first_line) of the drive flanks' contact lines that ``geometry`` lays out on
    ``mesh``'s path (:func:`jaxgear._extended.line_range`)."""
    lead = mesh.face_width * jnp.tan(mesh.base_helix_angle)
    first, last = line_range(mesh.path_of_contact, mesh.base_pitch, lead, geometry.line_span(mesh))
    return last - first + 1, first
