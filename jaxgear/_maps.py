"""Maps derived from quasi-static results: the load map over a tooth's passage, the Harris map
(TE peak-to-peak against torque) and the loaded path of contact against torque (with contact
beyond the theoretical path; docs/extended-contact.md)."""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ._baseplane import MeshModel, mesh_positions
from ._contact_geometry import TheoreticalPath
from ._contact import ContactLaw, ExactContact
from ._modifications import Modifications
from ._quasi_static import QuasiStaticResult, at_torques, per_mesh_modifications, separation
from ._results import ContactResult, raise_if_failed
from ._util import compiled_when_eager
from .scenes import cache_window_compliance

__all__ = ["LoadedPath", "harris_map", "load_map", "loaded_path"]


def load_map(
    r: QuasiStaticResult,
    positions_per_pitch: int,
    base_pitch: float,
    path_of_contact: float,
    field=None,
):
    """Maximum line load (N/m) over a tooth's passage on a grid of the base plane; ``field``: a
    cell field of the shape of ``r.line_load`` mapped instead (the contact pressure of
    :func:`~jaxgear.contact_pressure`, Pa).

    Every tooth pair meets the same cells (no pitch deviations), so the maximum over all positions
    and contact lines at a base-plane point is the maximum over one tooth's passage.

    Returns:
        (s_edges (n_s+1,), z (N,), load (n_s, N)): bin edges along the line of action (m), from
        0 to the path of contact (with contact beyond the theoretical path,
        docs/extended-contact.md: from the first to the last bin a loaded cell reaches beyond
        its ends), slice mid-points across the face (m), and the maximum line load per bin
        (N/m; NaN where no cell passed).

    The n_s = floor(path / step) bins are equal and at least one position step wide, the step
    of the contact lines along s (base pitch / positions per pitch): every slice's cells pass
    through every bin, so no bin inside the path is left empty (bins of exactly one step with
    a last, partial bin beyond the path left that bin empty on slices whose samples missed it).
    """
    ds = base_pitch / positions_per_pitch
    n_s = max(1, int(math.floor(path_of_contact / ds)))
    width = path_of_contact / n_s
    s = np.asarray(r.cell_s).reshape(-1, r.cell_s.shape[-1])
    p = np.asarray(r.line_load if field is None else field).reshape(s.shape)
    mask = np.asarray(r.cell_mask).reshape(s.shape)
    # bins beyond the ends as far as a loaded cell reaches (contact beyond the path)
    loaded = s[mask & (p > 0)]
    n_lo = int(math.ceil(max(0.0, -loaded.min()) / width * (1 - 1e-9))) if loaded.size else 0
    n_hi = (
        int(math.ceil(max(0.0, loaded.max() - path_of_contact) / width * (1 - 1e-9)))
        if loaded.size
        else 0
    )
    lo, hi = -n_lo * width, path_of_contact + n_hi * width
    n = n_lo + n_s + n_hi
    tol = 1e-9 * width
    keep = mask & (s >= lo - tol) & (s <= hi + tol)  # on the path: every cell on the flanks
    idx = np.clip(np.floor((s - lo) / width).astype(int), 0, n - 1)
    out = np.full((n, s.shape[1]), -np.inf)
    cols = np.broadcast_to(np.arange(s.shape[1]), s.shape)
    np.maximum.at(out, (idx[keep], cols[keep]), p[keep])
    out[~np.isfinite(out)] = np.nan
    z = np.asarray(r.cell_z)[0, 0]
    return np.linspace(lo, hi, n + 1), z, out


def harris_map(
    mesh,
    mods: Modifications,
    torques,
    contact: ContactLaw = ExactContact(),
    positions_per_pitch: int = 64,
) -> np.ndarray:
    """TE peak-to-peak (m) against pinion torque (N·m), vmapped over the torques, shape (T,);
    ``contact``: the contact law of :func:`~jaxgear.quasi_static`. A hybrid scene's window
    compliance is cached once for the sweep (:func:`~jaxgear.scenes.cache_window_compliance`;
    the same values)."""
    mesh = cache_window_compliance(mesh, positions_per_pitch=positions_per_pitch)

    # the torques checked and the result codes read on the host: the vmapped solve holds no
    # eqx.error_if callback, which JAX's persistent compilation cache does not store
    te, result = at_torques(
        mesh,
        mods,
        torques,
        lambda r: r.te_ptp,
        contact=contact,
        positions_per_pitch=positions_per_pitch,
    )
    raise_if_failed(result, ContactResult, "harris_map")
    return np.asarray(te)


class LoadedPath(eqx.Module):
    """The loaded path of contact of one mesh at each torque (arrays shaped (T,)).

    Attributes:
        torque: pinion torques (N·m).
        start, end: base-plane coordinates s (m) of the loaded path's ends: the smallest and
            the largest s of a loaded cell over the period (s < 0: premature engagement, s >
            g_α: late disengagement; 0 and g_α within a position's step at zero load).
        relief_start, relief_end: flank-normal depth (m) of extra tip relief at the driven
            gear's tip (``relief_start``) and at the pinion's tip (``relief_end``) that keeps
            its corner off the mating flank: the largest approach of the mesh without contact
            beyond the path (the theoretical model at the same torque) less the corner's
            separation, over the cells beyond each end; 0 where no corner touches.
        path_of_contact: g_α (m), a scalar.
    """

    torque: Float[Array, " T"]
    start: Float[Array, " T"]
    end: Float[Array, " T"]
    relief_start: Float[Array, " T"]
    relief_end: Float[Array, " T"]
    path_of_contact: Float[Array, ""]


def loaded_path(
    mesh: MeshModel,
    modifications: Modifications | None,
    torques,
    *,
    positions_per_pitch: int = 256,
) -> LoadedPath:
    """The loaded path of contact of the rigid pair ``mesh`` at pinion torques ``torques``:
    beside the Harris map (:func:`harris_map`, the TE's peak-to-peak over torque), where
    contact really starts and ends with the cells beyond the theoretical path, and the tip
    relief that would keep the corners off the mating flanks (docs/extended-contact.md).

    Args:
        mesh: a :class:`~jaxgear.MeshModel` built with ``contact_geometry=BeyondPath()``.
        modifications: its flank modifications (``None``: perfect involutes).
        torques: pinion torques (N·m), concrete, > 0, shape (T,).
        positions_per_pitch: positions per mesh period (>= 2); the ends are resolved to one
            position's roll, p_bt / ``positions_per_pitch``.

    Returns:
        :class:`LoadedPath`.

    Raises:
        ValueError: ``mesh`` not built with :class:`~jaxgear.BeyondPath`; bad torques or
            positions.
    """
    if not isinstance(mesh, MeshModel) or not mesh.contact_geometry.reaches_beyond_path:
        raise ValueError(
            "loaded_path: mesh must be a jaxgear.MeshModel with contact beyond the path "
            "(MeshModel.from_pair(..., contact_geometry=jaxgear.BeyondPath()))"
        )
    theoretical = mesh.with_contact_geometry(TheoreticalPath())
    mods = per_mesh_modifications(modifications, 1)[0]

    def loaded(r):
        m = r.meshes[0]
        on = m.line_load > 0
        big = jnp.asarray(jnp.inf, m.cell_s.dtype)
        return (
            jnp.min(jnp.where(on, m.cell_s, big)),
            jnp.max(jnp.where(on, m.cell_s, -big)),
        )

    (start, end), codes_ext = at_torques(
        mesh, modifications, torques, loaded, positions_per_pitch=positions_per_pitch
    )
    te, codes = at_torques(
        theoretical,
        modifications,
        torques,
        lambda r: r.meshes[0].transmission_error,
        positions_per_pitch=positions_per_pitch,
    )
    for c in (codes_ext, codes):
        if bool(jnp.any(c != 0)):
            raise ValueError("loaded_path: the contact solve failed at some torque and position")
    theta = mesh_positions(mesh, positions_per_pitch)
    relief_start, relief_end = _corner_relief(mesh, mods, theta, te)
    return LoadedPath(
        torque=jnp.asarray(torques, te.dtype),
        start=start,
        end=end,
        relief_start=relief_start,
        relief_end=relief_end,
        path_of_contact=mesh.path_of_contact,
    )


@compiled_when_eager
def _corner_relief(mesh, mods, theta, te):
    """The extra tip relief at the start and at the end that keeps every corner cell open at
    each torque (one compiled program when called eagerly: the separations at every position,
    then the maxima; traced inline under a caller's transformation)."""
    cells, e_max, delta0 = jax.vmap(lambda t: separation(mesh, mods, t))(theta)
    beyond = cells.mask & ((cells.s < 0) | (cells.s > mesh.path_of_contact))
    # the approach of the theoretical model u = TE cos β_b + max e, against each corner cell's
    # separation (max e − e + gap): what extra relief at the corner keeps it open
    approach = te * jnp.cos(mesh.base_helix_angle) + e_max[None, :]  # (T, P)
    over = approach[:, :, None, None] - delta0[None]

    def side(where):
        return jnp.maximum(jnp.max(jnp.where(where[None], over, 0.0), axis=(1, 2, 3)), 0.0)

    return side(beyond & (cells.s < 0)), side(beyond & (cells.s > mesh.path_of_contact))
