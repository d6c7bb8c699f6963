"""Maps derived from quasi-static results: the load map over a tooth's passage and the Harris map
(TE peak-to-peak against torque)."""

from __future__ import annotations

import math

import numpy as np

from ._contact import ContactLaw, ExactContact
from ._modifications import Modifications
from ._quasi_static import QuasiStaticResult, at_torques
from ._results import ContactResult, raise_if_failed
from .scenes import cache_window_compliance

__all__ = ["harris_map", "load_map"]


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
        0 to the path of contact, slice mid-points across the face (m), and the maximum line load
        per bin (N/m; NaN where no cell passed).

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
    idx = np.clip(np.floor(s / width).astype(int), 0, n_s - 1)
    out = np.full((n_s, s.shape[1]), -np.inf)
    cols = np.broadcast_to(np.arange(s.shape[1]), s.shape)
    np.maximum.at(out, (idx[mask], cols[mask]), p[mask])
    out[~np.isfinite(out)] = np.nan
    z = np.asarray(r.cell_z)[0, 0]
    return np.linspace(0.0, path_of_contact, n_s + 1), z, out


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
