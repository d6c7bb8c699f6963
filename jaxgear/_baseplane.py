"""Base-plane discretisation: contact lines cut into thin slices (cells).

Conventions: docs/design.md, "Base plane and sign conventions".

The base plane is spanned by s ∈ [0, g_α] along the transverse line of action (s = 0 at the
engagement point, where the gear tip meets the pinion's start of active profile; s = g_α at the
pinion tip) and z ∈ [0, b] across the effective face width. Tooth pair ``i``'s contact line at
pinion angle θ is ``s = r_b1 θ + i p_bt − z tan β_b``; each line is cut into N slices of equal
face width b/N, whose mid-points are the cells. Arrays have the fixed shape (n_lines, n_slices)
with a mask for the cells inside [0, g_α], so shapes never change under jit.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.linalg import block_diag
from jaxtyping import Array, Bool, Float, Int

from ._backlash import cell_flank, coast_phase
from ._contact_geometry import (
    AbstractContactGeometry,
    TheoreticalPath,
    contact_geometry_of,
    line_layout,
)
from ._extended import line_range
from ._geometry import GearPair
from ._util import as_float, check_instance, compiled_when_eager

__all__ = [
    "CellRow",
    "Cells",
    "MeshModel",
    "cell_flank",
    "check_positions",
    "coast_phase",
    "mesh_positions",
    "on_the_path",
    "split_by_mesh",
]


def _interp_uniform(x, xp, fp):
    """Linear interpolation on an equally spaced table (clamped at the ends); cheaper than
    ``jnp.interp``'s search. ``MeshModel.from_pair`` checks that the table is equally spaced."""
    n = xp.shape[0]
    t = (x - xp[0]) / (xp[-1] - xp[0]) * (n - 1)
    i = jnp.clip(jnp.floor(t), 0, n - 2)
    w = jnp.clip(t - i, 0.0, 1.0)
    return _lerp_rows(fp[:, None], i.astype(jnp.int32), w[..., None])[..., 0]


def _lerp_rows(table, row, w):
    """table[row] (1 − w) + table[row + 1] w, shape (..., c), for a table (m, c), row indices
    (...) in [0, m − 2] and weights w (..., 1): the two rows from one gather of the table's
    neighbouring rows side by side (XLA's CPU gather costs per index more than per value)."""
    c = table.shape[1]
    pairs = jnp.concatenate([table[:-1], table[1:]], axis=1)
    both = pairs.at[row].get(mode="promise_in_bounds")
    return both[..., :c] * (1.0 - w) + both[..., c:] * w


class Cells(eqx.Module):
    """Contact cells at one pinion angle (every array has shape (n_lines, n_slices)).

    Attributes:
        s: base-plane coordinate along the line of action (m).
        z: coordinate across the face (m).
        length: cell length along its contact line, (b/N)/cos β_b (m).
        stiffness: k_ij, stiffness per unit contact length (N/m²), flank-normal.
        mask: True where the cell lies on the flanks (0 <= s <= g_α).
        line: tooth-pair index of each cell's contact line (integer-valued floats).
        theta: the pinion angle (rad) these cells belong to, a scalar (bodies that rotate under
            the mesh, such as condensed FE bodies, need the absolute angle, not only the roll).
        flank: +1 on the drive flanks, −1 on the coast flanks (the second base plane of a
            :class:`MeshModel` with ``coast``; docs/backlash.md). The coast cells' s and z are
            in their own base plane (s from its engagement point, z mirrored: the π-rotation
            about the centre line that maps one flank of a symmetric tooth onto the other).
    """

    s: Float[Array, "n_lines n_slices"]
    z: Float[Array, "n_lines n_slices"]
    length: Float[Array, "n_lines n_slices"]
    stiffness: Float[Array, "n_lines n_slices"]
    mask: Bool[Array, "n_lines n_slices"]
    line: Float[Array, "n_lines n_slices"]
    theta: Float[Array, ""]
    flank: Float[Array, "n_lines n_slices"] | None = None


class CellRow(NamedTuple):
    """The cells of one mesh position flattened for the contact solvers (c = n_lines·n_slices
    cells, in the order of :class:`Cells`' arrays read row by row).

    Attributes:
        idx: the window W of coordinates the cells see, (w,) int, or None: all coordinates.
        V: structure vectors on the window (m per unit coordinate), (c, w) (w = n for None).
        k: cell stiffness per unit length (N/m²), (c,). length: cell length (m), (c,).
        delta0: initial separation δ0 (m), (c,).
        mask: cells on the flanks, (c,).
    """

    idx: Int[Array, " w"] | None
    V: Float[Array, "c w"]
    k: Float[Array, " c"]
    length: Float[Array, " c"]
    delta0: Float[Array, " c"]
    mask: Bool[Array, " c"]

    @classmethod
    def of(cls, cells: Cells, V, delta0, idx=None) -> CellRow:
        """Flatten ``cells`` (n_lines, n_slices) with their structure vectors ``V``
        (n_lines, n_slices, w) or (c, w) and initial separations ``delta0`` (n_lines, n_slices)
        (m) on the window ``idx`` (None: all coordinates)."""
        return cls(
            idx,
            V.reshape(-1, V.shape[-1]),
            cells.stiffness.reshape(-1),
            cells.length.reshape(-1),
            delta0.reshape(-1),
            cells.mask.reshape(-1),
        )

    @classmethod
    def concat(cls, rows: Sequence[CellRow]) -> CellRow:
        """The cells of several meshes in one row, mesh after mesh.

        On all coordinates (every ``idx`` None) the vectors stack. On windows the window is the
        meshes' windows one after the other (a coordinate that two meshes see, such as a gear
        meshing twice, appears once per mesh) and V is block diagonal, (Σc, Σw): V_W G_WW V_Wᵀ
        then holds the cross-compliance between the meshes, and scatters back by adding.

        Raises:
            ValueError: no rows, or rows on all coordinates mixed with rows on windows.
        """
        if not rows:
            raise ValueError("a scene needs at least one gear mesh")
        if len(rows) == 1:
            return rows[0]
        windowed = {r.idx is not None for r in rows}
        if len(windowed) != 1:
            raise ValueError("cell rows on all coordinates cannot be joined with rows on windows")
        if windowed == {True}:
            idx = jnp.concatenate([r.idx for r in rows])
            V = block_diag(*(r.V for r in rows))
        else:
            idx, V = None, jnp.concatenate([r.V for r in rows])
        return cls(
            idx,
            V,
            *(
                jnp.concatenate([getattr(r, f) for r in rows])
                for f in ("k", "length", "delta0", "mask")
            ),
        )


def split_by_mesh(values, shapes) -> tuple:
    """``values`` (..., c) over the cells of several meshes, mesh after mesh (as
    :meth:`CellRow.concat` joins them), cut into each mesh's (..., n_lines, n_slices) for the
    ``shapes`` (n_lines, n_slices) of the meshes."""
    out, start = [], 0
    for L, N in shapes:
        part = values[..., start : start + L * N]
        out.append(part.reshape(part.shape[:-1] + (L, N)))
        start += L * N
    return tuple(out)


class MeshModel(eqx.Module):
    """The gear mesh in the base plane: geometry scalars, stiffness table and cell layout.

    Build it with :meth:`from_pair`. Dynamic leaves are arrays (constants for gradients unless you
    differentiate through them); ``n_lines``, ``n_slices`` and ``first_line`` are static shapes.

    Attributes:
        path_of_contact: g_α (m). base_pitch: p_bt (m). face_width: b (m).
        base_radius_pinion, base_radius_gear: r_b1, r_b2 (m).
        base_helix_angle: β_b (rad).
        contact_ratio: ε_α (-).
        stiffness_s, stiffness_k: the table k(s) (m, N/m²), shape (n_table,).
        backlash: normal backlash j_bn (m) between the coast flanks when the drive flanks touch
            (:class:`~jaxgear.GearPair` ``normal_backlash``); used with ``coast``.
        coast_angle: θ_c (rad): the coast cells at pinion angle θ are the layout's cells at
            θ_c − θ (docs/backlash.md, "Coast flank").
        coast: static; True: the cells hold the coast flanks too (rows ``n_drive_lines`` on,
            ``flank`` −1), whose contact closes when the motion takes up the backlash.
        extension_span: (S_a, S_r) (m), how far the cells reach before the theoretical start of
            contact (s ∈ [−S_a, 0)) and after its end (s ∈ (g_α, g_α + S_r]); (0, 0) for a model
            built on the theoretical path alone.
        extension_gap: the tip-corner gaps there (m, transverse, :class:`jaxgear.CornerContact`),
            shape (2, n_ext): row 0 at s = −S_a u, row 1 at s = g_α + S_r u, u equally spaced
            on [0, 1].
        extension_corner: where a corner cell's force acts, shape (2, 4, n_ext) on the grid of
            ``extension_gap``: the tip owner's lever ratio λ, the normal's angle ε (rad) from
            the line of action and the contact point's offset (o_t, o_v) (m) from the line of
            action (:func:`jaxgear._extended.corner_table`; :meth:`corner`).
        contact_geometry: static; where the teeth can touch
            (:class:`~jaxgear.AbstractContactGeometry`): :class:`~jaxgear.TheoreticalPath`
            (default) or :class:`~jaxgear.BeyondPath`, contact beyond the theoretical path too
            (premature engagement and late disengagement at the tip corners;
            docs/extended-contact.md).
        n_lines: static, the rows of the cell arrays (drive and coast lines with ``coast``).
    """

    path_of_contact: Float[Array, ""] = eqx.field(converter=as_float)
    base_pitch: Float[Array, ""] = eqx.field(converter=as_float)
    face_width: Float[Array, ""] = eqx.field(converter=as_float)
    base_radius_pinion: Float[Array, ""] = eqx.field(converter=as_float)
    base_radius_gear: Float[Array, ""] = eqx.field(converter=as_float)
    base_helix_angle: Float[Array, ""] = eqx.field(converter=as_float)
    contact_ratio: Float[Array, ""] = eqx.field(converter=as_float)
    stiffness_s: Float[Array, " n_table"] = eqx.field(converter=as_float)
    stiffness_k: Float[Array, " n_table"] = eqx.field(converter=as_float)
    n_slices: int = eqx.field(static=True)
    n_lines: int = eqx.field(static=True)
    first_line: int = eqx.field(static=True)
    backlash: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    coast_angle: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    coast: bool = eqx.field(static=True, default=False)
    extension_span: Float[Array, " 2"] = eqx.field(converter=as_float, default=(0.0, 0.0))
    extension_gap: Float[Array, "2 n_ext"] = eqx.field(
        converter=as_float, default=((0.0, 0.0), (0.0, 0.0))
    )
    extension_corner: Float[Array, "2 4 n_ext"] = eqx.field(
        converter=as_float, default=(((1.0, 1.0), (0.0, 0.0), (0.0, 0.0), (0.0, 0.0)),) * 2
    )
    contact_geometry: AbstractContactGeometry = eqx.field(static=True, default=TheoreticalPath())

    def __check_init__(self):
        if self.n_slices < 1:
            raise ValueError(f"mesh.slices = {self.n_slices} is out of range: allowed >= 1")

    @classmethod
    def from_pair(
        cls,
        pair: GearPair,
        stiffness_s: np.ndarray,
        stiffness_k: np.ndarray,
        n_slices: int,
        coast: bool = False,
        contact_geometry: AbstractContactGeometry = TheoreticalPath(),
        extended_contact: bool | None = None,
    ) -> MeshModel:
        """Lay out cells for ``pair`` with ``n_slices`` slices per contact line.

        Args:
            pair: validated gear pair.
            stiffness_s, stiffness_k: k(s) table from :func:`jaxgear.stiffness_table` (the
                coast flanks of symmetric teeth take the same table in their base plane).
            n_slices: slices N per contact line (>= 1).
            coast: also lay out the coast flanks (the second base plane) with the pair's
                backlash (docs/backlash.md); default False: the drive flanks alone.
            contact_geometry: where the teeth can touch: :class:`~jaxgear.TheoreticalPath`
                (default), or :class:`~jaxgear.BeyondPath` to lay out cells beyond the
                theoretical path of contact too, where the tip corners can touch the mating
                flanks under load (:func:`jaxgear.extension_table`; docs/extended-contact.md).
            extended_contact: deprecated: ``True`` is ``contact_geometry=BeyondPath()``,
                ``False`` ``TheoreticalPath()`` (a DeprecationWarning).

        Raises:
            ValueError: bad slices or table; :class:`~jaxgear.BeyondPath` with ``coast``.
        """
        if extended_contact is not None:
            warnings.warn(
                "MeshModel.from_pair(extended_contact=...) is deprecated: pass "
                "contact_geometry=jaxgear.BeyondPath() (True) or jaxgear.TheoreticalPath() (False)",
                DeprecationWarning,
                stacklevel=2,
            )
            contact_geometry = contact_geometry_of(extended_contact)
        check_instance(
            "contact_geometry",
            contact_geometry,
            AbstractContactGeometry,
            "a jaxgear.AbstractContactGeometry (TheoreticalPath() or BeyondPath())",
            "MeshModel.from_pair",
        )
        if int(n_slices) != n_slices or n_slices < 1:
            raise ValueError(f"mesh.slices = {n_slices!r} is out of range: allowed an integer >= 1")
        ds = np.diff(np.asarray(stiffness_s, dtype=float))
        if ds.size < 1 or not np.allclose(ds, ds[0], rtol=1e-9) or ds[0] <= 0:
            raise ValueError(
                "stiffness_s must be an equally spaced, increasing table of >= 2 points "
                "(as stiffness_table returns)"
            )
        span, gap, corner = contact_geometry.tables(pair, bool(coast))
        lead = pair.face_width * math.tan(pair.base_helix_angle)
        first, last = line_range(pair.path_of_contact, pair.base_pitch, lead, span)
        n_lines = last - first + 1
        backlash = coast_angle = 0.0
        if coast:
            backlash = pair.normal_backlash
            coast_angle = coast_phase(pair)
        return cls(
            pair.path_of_contact,
            pair.base_pitch,
            pair.face_width,
            pair.base_radii[0],
            pair.base_radii[1],
            pair.base_helix_angle,
            pair.transverse_contact_ratio,
            stiffness_s,
            stiffness_k,
            n_slices=int(n_slices),
            n_lines=n_lines * (2 if coast else 1),
            first_line=first,
            backlash=backlash,
            coast_angle=coast_angle,
            coast=bool(coast),
            extension_span=span,
            extension_gap=gap,
            extension_corner=corner,
            contact_geometry=contact_geometry,
        )

    @property
    def extended_contact(self) -> bool:
        """Deprecated (a DeprecationWarning): whether the cells reach beyond the theoretical
        path, ``contact_geometry.reaches_beyond_path``."""
        warnings.warn(
            "MeshModel.extended_contact is deprecated: read "
            "mesh.contact_geometry (jaxgear.TheoreticalPath or jaxgear.BeyondPath)",
            DeprecationWarning,
            stacklevel=3,  # the caller's, past equinox's property access
        )
        return self.contact_geometry.reaches_beyond_path

    def with_contact_geometry(self, geometry: AbstractContactGeometry) -> MeshModel:
        """This mesh model with the contact geometry ``geometry`` and the contact lines it lays
        out (:class:`~jaxgear.TheoreticalPath`: the cells beyond the path dropped;
        :class:`~jaxgear.BeyondPath` needs the gap tables of :meth:`from_pair`).

        Raises:
            ValueError: :class:`~jaxgear.BeyondPath` for a model built without its tables.
        """
        check_instance(
            "contact_geometry",
            geometry,
            AbstractContactGeometry,
            "a jaxgear.AbstractContactGeometry (TheoreticalPath() or BeyondPath())",
            "MeshModel.with_contact_geometry",
        )
        if geometry == self.contact_geometry:
            return self
        n_lines, first = line_layout(self, geometry)
        return dataclasses.replace(
            self, n_lines=n_lines, first_line=first, contact_geometry=geometry
        )

    def with_extended_contact(self, extended: bool) -> MeshModel:
        """Deprecated (a DeprecationWarning): :meth:`with_contact_geometry` of
        :class:`~jaxgear.BeyondPath` (``True``) or :class:`~jaxgear.TheoreticalPath`
        (``False``)."""
        warnings.warn(
            "MeshModel.with_extended_contact is deprecated: use "
            "mesh.with_contact_geometry(jaxgear.TheoreticalPath()) (or BeyondPath())",
            DeprecationWarning,
            stacklevel=3,  # the caller's, past equinox's bound method
        )
        return self.with_contact_geometry(contact_geometry_of(extended))

    @property
    def base_planes(self) -> tuple[MeshModel]:
        """``(self,)``: a mesh model is the one base plane of its rigid pair, as a scene's
        ``base_planes`` are (:class:`jaxgear.scenes.Scene`)."""
        return (self,)

    @property
    def n_drive_lines(self) -> int:
        """Contact lines of the drive flanks (the first rows of the cell arrays)."""
        return self.n_lines // 2 if self.coast else self.n_lines

    @property
    def mesh_period_angle(self) -> Float[Array, ""]:
        """Pinion rotation of one mesh period, p_bt / r_b1 = 2π/z1 (rad)."""
        return self.base_pitch / self.base_radius_pinion

    def cells(self, theta: Float[Array, ""]) -> Cells:
        """Cells at pinion angle ``theta`` (rad, from a position where a contact line is at s=0).

        Only the angle modulo one mesh period matters: the cells (layout, stiffness, mask)
        repeat every period; per-tooth deviations enter through the initial separation, at the
        absolute angle (:func:`jaxgear.separation`, ``Modifications.deviations``). With
        ``coast`` the coast lines follow the drive lines: rows ``n_drive_lines`` on, at the
        layout's angle θ_c − θ in the second base plane (``flank`` −1; docs/backlash.md).
        """
        return _compiled_cells(self, jnp.asarray(theta))

    def _cells(self, theta) -> Cells:
        """:meth:`cells` (traced, or compiled once per mesh layout when called eagerly)."""
        dz = self.face_width / self.n_slices
        z = (jnp.arange(self.n_slices) + 0.5) * dz
        L = self.n_drive_lines
        line = jnp.arange(L, dtype=float) + self.first_line

        def layout(angle):
            roll = jnp.mod(self.base_radius_pinion * angle, self.base_pitch)
            return (
                roll + line[:, None] * self.base_pitch - z[None, :] * jnp.tan(self.base_helix_angle)
            )

        s = layout(theta)
        flank = jnp.ones(s.shape, s.dtype)
        if self.coast:
            s = jnp.concatenate([s, layout(self.coast_angle - theta)])
            flank = jnp.concatenate([flank, -flank])
            line = jnp.concatenate([line, line])
        lo, hi = self.contact_geometry.cell_range(self)
        mask = (s >= lo) & (s <= hi)
        k = _interp_uniform(s, self.stiffness_s, self.stiffness_k)
        length = jnp.broadcast_to(dz / jnp.cos(self.base_helix_angle), s.shape)
        zz = jnp.broadcast_to(z[None, :], s.shape)
        ll = jnp.broadcast_to(line[:, None], s.shape)
        return Cells(
            s=s,
            z=zz,
            length=length,
            stiffness=k,
            mask=mask,
            line=ll,
            theta=jnp.asarray(theta, s.dtype),
            flank=flank,
        )

    def extension_separation(self, s: Float[Array, "..."]) -> Float[Array, "..."]:
        """The flank-normal tip-corner gap (m) at base-plane coordinates ``s`` (m): 0 on the
        theoretical path [0, g_α] and on a :class:`~jaxgear.TheoreticalPath`; beyond it the
        table ``extension_gap`` × cos β_b (interpolated)."""
        return self.contact_geometry.corner_gap(self, s)

    def corner(self, s: Float[Array, "..."]) -> tuple:
        """Where the force of a cell at base-plane coordinates ``s`` (m) acts
        (docs/extended-contact.md, "Where it acts"): ``(lever_driving, lever_driven, eps,
        o_t, o_v)``, arrays shaped like ``s``. Beyond the theoretical path the tip owner (the
        driven gear before the start, s < 0; the driving gear after the end, s > g_α) has the
        lever ratio λ(s) = d_T/r_bT, the flank owner 1 (its normal is tangent to its base
        circle); ε (rad) turns the transverse normal from the line of action (t' = cos ε t −
        sin ε v, v the unit vector from the driving gear's centre to its tangent point T1) and
        the contact point (the corner) sits at M + o_t t + o_v v. On the path, and on a
        :class:`~jaxgear.TheoreticalPath`: (1, 1, 0, 0, 0). Source:
        :class:`jaxgear.CornerContact`."""
        return self.contact_geometry.corner(self, s)

    def _beyond_path(self, s) -> tuple:
        """(beyond, after, values) at base-plane coordinates ``s`` (m): whether each cell lies
        beyond the theoretical path (s < 0 or s > g_α), whether after its end, and the tables
        of its side (row 0 at s = −S_a u, row 1 at s = g_α + S_r u, u equally spaced on
        [0, 1], clamped at the ends) linearly interpolated, shape (..., 5): the corner gap
        (``extension_gap``, transverse) and ``extension_corner``'s λ, ε, o_t, o_v. One index
        and one gather for every channel and both sides, the same in :meth:`corner` and
        :meth:`extension_separation` (a program that calls both computes it once: XLA merges
        the two). On the path the values are row 0's at its clamped start: callers replace
        them."""
        table = jnp.concatenate(
            [self.extension_gap[..., None], jnp.moveaxis(self.extension_corner, 1, 2)], axis=-1
        )
        n = table.shape[1]
        span = jnp.maximum(self.extension_span, jnp.finfo(s.dtype).tiny)
        after = s > self.path_of_contact
        u = jnp.where(after, (s - self.path_of_contact) / span[1], -s / span[0])
        t = u * (n - 1)  # the grid's u_0 = 0 and u_{n-1} = 1 exactly: _interp_uniform's t
        i = jnp.clip(jnp.floor(t), 0, n - 2)
        w = jnp.clip(t - i, 0.0, 1.0)[..., None]
        row = after.astype(jnp.int32) * n + i.astype(jnp.int32)
        values = _lerp_rows(table.reshape(2 * n, table.shape[2]), row, w)
        return (s < 0.0) | after, after, values

    def extension_overrun(self, cells: Cells, gap: Float[Array, "L N"]) -> Bool[Array, ""]:
        """Whether the solved approach would close the corner gap past the far end of the
        cells beyond the path (the extension too short): a cell beyond the path whose own
        approach, less its separation without the corner gap, exceeds the corner gap at its
        side's end, i.e. Δ_c + g(s_c) > g_end (``gap`` Δ = V·X − δ0 of each cell, m,
        flank-normal, from the contact solve; g the corner gap :meth:`extension_separation`).

        Each cell's approach is its own (V·X at the cell: a condensed body's rim deflection,
        a shaft's tilt included), compared with the separation it would have at the
        extension's end: like with like. The mesh's approach on the members' coordinates
        (u·X, the TE's) is not the cells': with a condensed body it holds the body's twist
        between the hub and the rim, which closes no gap. False on a
        :class:`~jaxgear.TheoreticalPath`."""
        return self.contact_geometry.overrun(self, cells, gap)

    def normal_load(self, torque: Float[Array, ""]) -> Float[Array, ""]:
        """Flank-normal mesh force F_n = T / (r_b1 cos β_b) (N) for pinion torque T (N·m)."""
        return torque / (self.base_radius_pinion * jnp.cos(self.base_helix_angle))


#: :meth:`MeshModel.cells` in one program when called on concrete values (eagerly its few
#: dozen operations compile one by one for each new layout)
_compiled_cells = compiled_when_eager(lambda mesh, theta: mesh._cells(theta))


def on_the_path(tree):
    """``tree`` (a :class:`MeshModel`, or a pytree holding mesh models: a planetary stage's
    meshes, a gearbox stage) with each mesh model's cells beyond the theoretical path masked
    off, the shapes kept (the lines laid out stay, the contact geometry
    :class:`~jaxgear.TheoreticalPath`: :meth:`~jaxgear.AbstractContactGeometry.on_path`): the
    cells that a
    mean over the flanks at no load takes (K̄_m of the modes and of the modal damping, the
    unloaded mesh stiffness). Beyond the path a cell holds the corner's gap and carries load only
    where the deflection closes it (docs/extended-contact.md), so counting it as a spring there
    would stiffen those means. ``tree`` itself where no mesh model in it has cells beyond the
    path."""
    is_mesh = lambda x: isinstance(x, MeshModel)
    meshes = [m for m in jax.tree.leaves(tree, is_leaf=is_mesh) if is_mesh(m)]
    if all(m.contact_geometry.on_path(m) is m for m in meshes):
        return tree
    return jax.tree.map(
        lambda x: x.contact_geometry.on_path(x) if is_mesh(x) else x, tree, is_leaf=is_mesh
    )


def mesh_positions(
    mesh: MeshModel, positions_per_pitch: int, periods: int = 1
) -> Float[Array, " P"]:
    """Pinion angles (rad) at the mid-points of ``positions_per_pitch`` steps per mesh period.

    Mid-points keep contact-line ends off the exact edges s = 0 and s = g_α.
    """
    check_positions(positions_per_pitch, periods)
    k = jnp.arange(positions_per_pitch * periods, dtype=mesh.base_pitch.dtype) + 0.5
    return k * mesh.mesh_period_angle / positions_per_pitch


def check_positions(positions_per_pitch, periods) -> None:
    """One-line errors for position counts: ``positions_per_pitch`` an integer >= 2, ``periods``
    an integer >= 1.

    Raises:
        ValueError: either out of range (naming the setting and the allowed range).
    """
    if int(positions_per_pitch) != positions_per_pitch or positions_per_pitch < 2:
        raise ValueError(
            f"mesh.positions_per_pitch = {positions_per_pitch!r} is out of range: "
            "allowed an integer >= 2"
        )
    if int(periods) != periods or periods < 1:
        raise ValueError(f"periods = {periods!r} is out of range: allowed an integer >= 1")
