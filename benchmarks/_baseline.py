"""Independent NumPy/SciPy baseline of the quasi-static rigid-mesh transmission error.

This is the reference the benchmark (``jaxgear bench quasi-static``) and ``tests/test_baseline.py``
compare jaxgear against. It is written the way a careful engineer would write it without JAX, and
shares no numerical code with the JAX kernels: only the gear geometry and the stiffness table
(both NumPy, evaluated once) come from :mod:`jaxgear._geometry` / :mod:`jaxgear._stiffness`.

Model (rigid 1-DOF mesh; docs/design.md, "Base plane and sign conventions" to "Contact laws"):
at pinion angle θ, tooth pair ``i``'s contact line is
``s = (r_b1 θ mod p_bt) + i p_bt − z tan β_b``, cut into N slices of width b/N (cell mid-points,
cell length l = (b/N)/cos β_b). A cell exists when 0 <= s <= g_α; its stiffness per unit length
k(s) is interpolated linearly in the table. The pair deviation is e = e_pinion(u = s/g_α, ζ)
+ e_gear(u = 1 − s/g_α, ζ) with ζ = z/b, the initial separation δ0 = max e − e, and the approach
δ of the rigid mesh solves the scalar monotone equation

    f(δ) = Σ_cells k l φ(δ − δ0) − F_n = 0,   F_n = T / (r_b1 cos β_b),

with φ(Δ) = max(0, Δ) (exact) or φ_w(Δ) = w log(1 + exp(Δ/w)) (smooth). It is solved per position
by :func:`scipy.optimize.brentq` on a bracket where f changes sign. The transverse transmission
error is TE = (δ − max e)/cos β_b.

With contact beyond the theoretical path (``BaselineMesh.extension_span`` > 0; docs/
extended-contact.md) the cells run from s = −S_a to g_α + S_r. A cell beyond the path has the
stiffness of the path's end (the table clamped), the deviation of the path's end, and the
tip-corner gap g(s) cos β_b added to its δ0; after the end of the path the pinion's tip corner
touches with the lever arm λ(s) r_b1, so the cell's approach is λ δ and its force acts with
λ on the pinion's torque:

    f(δ) = Σ_cells V k l φ(V δ − δ0) − F_n,   V = λ(s) after the end, 1 elsewhere.

The gap and λ tables are geometry (:func:`jaxgear.extension_table`,
:func:`jaxgear.corner_table`: NumPy, evaluated once), interpolated here linearly.

Everything is plain NumPy: vectorised over the cells of one position, a Python loop over
positions.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
from scipy.optimize import brentq

__all__ = ["BaselineMesh", "baseline_mesh", "member_params", "mods_params", "te_curve_numpy"]

_EPS = np.finfo(float).eps


@dataclasses.dataclass(frozen=True)
class BaselineMesh:
    """Plain-number description of the gear mesh (SI units).

    Attributes:
        path_of_contact: g_α (m). base_pitch: p_bt (m). face_width: b (m).
        base_radius_pinion: r_b1 (m). base_helix_angle: β_b (rad).
        stiffness_s, stiffness_k: table k(s) (m, N/m²), shape (n_table,), s ascending.
        n_slices: slices N per contact line.
        extension_span: (S_a, S_r) (m), how far the cells reach beyond the path's start and
            end; (0, 0): the theoretical path only.
        extension_gap: the tip-corner gaps (m, transverse), shape (2, n_ext): row 0 at s =
            −S_a u, row 1 at s = g_α + S_r u, u = linspace(0, 1, n_ext); None without.
        extension_lever: the pinion tip corner's lever ratio λ after the end of the path, on
            row 1's grid, shape (n_ext,); None without.
    """

    path_of_contact: float
    base_pitch: float
    face_width: float
    base_radius_pinion: float
    base_helix_angle: float
    stiffness_s: np.ndarray
    stiffness_k: np.ndarray
    n_slices: int
    extension_span: tuple = (0.0, 0.0)
    extension_gap: np.ndarray | None = None
    extension_lever: np.ndarray | None = None

    @property
    def extended(self) -> bool:
        """Whether the cells reach beyond the theoretical path."""
        return self.extension_gap is not None

    def line_indices(self) -> np.ndarray:
        """Tooth-pair indices i whose line can reach [−S_a, g_α + S_r] at some roll in
        [0, p_bt).

        s = roll + i p_bt − z tan β_b with roll ∈ [0, p_bt) and z tan β_b ∈ [0, b tan β_b]: a
        line with (i + 1) p_bt <= −S_a has s < −S_a everywhere, and one with i p_bt − b tan β_b
        > g_α + S_r has s > g_α + S_r everywhere, so i runs over floor(−S_a/p_bt) …
        ceil((g_α + S_r + b tan β_b)/p_bt) (0 … ceil(ε_α + ε_β) on the theoretical path).
        """
        lead = self.face_width * math.tan(self.base_helix_angle)
        lo = math.floor(-self.extension_span[0] / self.base_pitch)
        hi = math.ceil((self.path_of_contact + self.extension_span[1] + lead) / self.base_pitch)
        return np.arange(lo, hi + 1, dtype=float)


def baseline_mesh(
    case,
    slices: int | None = None,
    torque: float | None = None,
    extended_contact: bool | None = None,
) -> BaselineMesh:
    """:class:`BaselineMesh` of a :class:`jaxgear.io.Case` (geometry and k(s) table in NumPy).

    The stiffness table is the same one :meth:`jaxgear.io.Case.mesh_model` uses (evaluated at the
    nominal line load of ``torque``, default the case torque). ``extended_contact``: the cells
    beyond the theoretical path (the corner gap and lever tables of the pair's geometry);
    None: as the case has it.
    """
    from jaxgear import corner_table, extension_table, stiffness_table  # NumPy only

    pair = case.pair
    s, k = stiffness_table(
        pair,
        case.stiffness,
        youngs_modulus=case.youngs_modulus,
        poisson_ratio=case.poisson_ratio,
        line_load=case.nominal_line_load(torque),
    )
    extended = (
        case.contact_geometry.reaches_beyond_path
        if extended_contact is None
        else bool(extended_contact)
    )
    ext = {}
    if extended:
        span, gap = extension_table(pair)
        ext = {
            "extension_span": (float(span[0]), float(span[1])),
            "extension_gap": np.asarray(gap, dtype=float),
            "extension_lever": np.asarray(corner_table(pair, span)[1, 0], dtype=float),
        }
    return BaselineMesh(
        path_of_contact=float(pair.path_of_contact),
        base_pitch=float(pair.base_pitch),
        face_width=float(pair.face_width),
        base_radius_pinion=float(pair.base_radii[0]),
        base_helix_angle=float(pair.base_helix_angle),
        stiffness_s=np.asarray(s, dtype=float),
        stiffness_k=np.asarray(k, dtype=float),
        n_slices=int(case.slices if slices is None else slices),
        **ext,
    )


def member_params(
    tip_relief_depth=0.0,
    tip_relief_extent=0.25,
    tip_relief_shape="linear",
    root_relief_depth=0.0,
    root_relief_extent=0.25,
    root_relief_shape="linear",
    crowning_depth=0.0,
    end_relief_depth=0.0,
    end_relief_extent=0.1,
    helix_slope_deviation=0.0,
    profile_deviation_roll=(0.0, 1.0),
    profile_deviation=(0.0, 0.0),
    relief_blend=0.0,
) -> dict[str, Any]:
    """One member's modification parameters as plain numbers (m, fractions; see
    :class:`jaxgear.MemberModification` for the meaning of each)."""
    return {
        "tip_relief_depth": float(tip_relief_depth),
        "tip_relief_extent": float(tip_relief_extent),
        "tip_relief_shape": str(tip_relief_shape),
        "root_relief_depth": float(root_relief_depth),
        "root_relief_extent": float(root_relief_extent),
        "root_relief_shape": str(root_relief_shape),
        "crowning_depth": float(crowning_depth),
        "end_relief_depth": float(end_relief_depth),
        "end_relief_extent": float(end_relief_extent),
        "helix_slope_deviation": float(helix_slope_deviation),
        "profile_deviation_roll": np.asarray(profile_deviation_roll, dtype=float),
        "profile_deviation": np.asarray(profile_deviation, dtype=float),
        "relief_blend": float(relief_blend),
    }


def mods_params(modifications=None) -> dict[str, dict[str, Any]]:
    """Plain-number parameters ``{"pinion": ..., "gear": ...}`` of a :class:`jaxgear.Modifications`
    (``None``: perfect involutes)."""
    out = {}
    for tag in ("pinion", "gear"):
        m = None if modifications is None else getattr(modifications, tag)
        if m is None:
            out[tag] = member_params()
            continue
        out[tag] = member_params(
            tip_relief_depth=float(m.tip_relief_depth),
            tip_relief_extent=float(m.tip_relief_extent),
            tip_relief_shape=m.tip_relief_shape.name,
            root_relief_depth=float(m.root_relief_depth),
            root_relief_extent=float(m.root_relief_extent),
            root_relief_shape=m.root_relief_shape.name,
            crowning_depth=float(m.crowning_depth),
            end_relief_depth=float(m.end_relief_depth),
            end_relief_extent=float(m.end_relief_extent),
            helix_slope_deviation=float(m.helix_slope_deviation),
            profile_deviation_roll=np.asarray(m.profile_deviation_roll),
            profile_deviation=np.asarray(m.profile_deviation),
            relief_blend=float(getattr(m, "relief_blend", 0.0)),
        )
    return out


def _relief_shape(x: np.ndarray, shape: str, blend: float) -> np.ndarray:
    """x (linear) or x² (parabolic) of x clipped to [0, 1]; with ``blend`` > 0 (x units) the
    lower clip is rounded to blend·log(1 + exp(x/blend))."""
    x = blend * np.logaddexp(0.0, x / blend) if blend > 0 else np.maximum(x, 0.0)
    x = np.minimum(x, 1.0)
    if shape == "linear":
        return x
    if shape == "parabolic":
        return x * x
    raise ValueError(f"relief shape = {shape!r}: allowed 'linear', 'parabolic'")


def _member_deviation(p: dict, u: np.ndarray, zeta: np.ndarray) -> np.ndarray:
    """Normal deviation (m, + = material added) of one member at roll fraction u and lead
    fraction ζ (arrays of the same shape)."""
    e = np.interp(u, p["profile_deviation_roll"], p["profile_deviation"])
    # tip relief over the last Γ of the active profile, root relief over the first Γ
    # (relief_blend rounds each relief start over that roll fraction)
    blend = p.get("relief_blend", 0.0)
    g = p["tip_relief_extent"]
    e = e - p["tip_relief_depth"] * _relief_shape(
        (u - 1.0 + g) / g, p["tip_relief_shape"], blend / g
    )
    g = p["root_relief_extent"]
    e = e - p["root_relief_depth"] * _relief_shape((g - u) / g, p["root_relief_shape"], blend / g)
    # lead: parabolic crowning (depth at both face edges), linear end relief, helix slope
    e = e - p["crowning_depth"] * (2.0 * zeta - 1.0) ** 2
    le = p["end_relief_extent"]
    e = e - p["end_relief_depth"] * (
        np.clip(1.0 - zeta / le, 0.0, 1.0) + np.clip((zeta - 1.0 + le) / le, 0.0, 1.0)
    )
    e = e + p["helix_slope_deviation"] * (zeta - 0.5)
    return e


def _positions(mesh: BaselineMesh, positions_per_pitch: int, periods: int) -> np.ndarray:
    period = mesh.base_pitch / mesh.base_radius_pinion
    return (np.arange(positions_per_pitch * periods) + 0.5) * period / positions_per_pitch


def _residual_exact(
    delta: float, delta0: np.ndarray, kl: np.ndarray, force: float, v: np.ndarray | None = None
) -> float:
    """Σ V k l max(0, V δ − δ0) − F_n (N) (V = 1: ``v`` None)."""
    if v is None:
        return float(np.dot(kl, np.maximum(delta - delta0, 0.0))) - force
    return float(np.dot(v * kl, np.maximum(v * delta - delta0, 0.0))) - force


def _residual_smooth(
    delta: float,
    delta0: np.ndarray,
    kl: np.ndarray,
    force: float,
    width: float,
    v: np.ndarray | None = None,
) -> float:
    """Σ V k l w log(1 + exp((V δ − δ0)/w)) − F_n (N), overflow-safe (V = 1: ``v`` None)."""
    if v is None:
        return float(np.dot(kl, width * np.logaddexp(0.0, (delta - delta0) / width))) - force
    return float(np.dot(v * kl, width * np.logaddexp(0.0, (v * delta - delta0) / width))) - force


def _beyond_path(mesh: BaselineMesh, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The flank-normal corner gap (m) and the lever V of cells at ``s`` (m): 0 and 1 on the
    path [0, g_α]; before it the gap of row 0 (V = 1: the pinion owns the flank); after it
    row 1's gap and λ."""
    g_alpha = mesh.path_of_contact
    span, table = mesh.extension_span, mesh.extension_gap
    u = np.linspace(0.0, 1.0, table.shape[1])
    gap = np.zeros_like(s)
    v = np.ones_like(s)
    before, after = s < 0.0, s > g_alpha
    gap[before] = np.interp(-s[before] / span[0], u, table[0])
    ua = (s[after] - g_alpha) / span[1]
    gap[after] = np.interp(ua, u, table[1])
    v[after] = np.interp(ua, u, mesh.extension_lever)
    return gap * math.cos(mesh.base_helix_angle), v


def te_curve_numpy(
    mesh: BaselineMesh,
    mods: dict | None,
    torque: float,
    contact: str = "exact",
    width: float = 1e-7,
    positions_per_pitch: int = 64,
    periods: int = 1,
    theta: np.ndarray | None = None,
) -> dict[str, np.ndarray]:
    """Quasi-static TE curve of the rigid mesh, NumPy + brentq per position.

    Args:
        mesh: :class:`BaselineMesh` (from :func:`baseline_mesh`).
        mods: ``{"pinion": member_params(...), "gear": member_params(...)}`` (``None``: none).
        torque: pinion torque T (N·m), > 0.
        contact: "exact" (φ = max(0, Δ)) or "smooth" (softplus ramp of ``width`` m).
        width: smoothing width w (m), smooth mode only.
        positions_per_pitch, periods: positions at the mid-points (k + 1/2) p_bt/(r_b1 P).
        theta: pinion angles (rad), shape (P,), overriding the default positions.

    Returns:
        dict with ``theta`` (rad), ``te`` (transverse TE, m), ``approach`` (δ, m),
        ``mesh_stiffness`` (Σ k l φ'(Δ), N/m), ``contact_length`` (Σ l φ'(Δ), m),
        ``evaluations`` (f evaluations by brentq), each shape (P,).

    Raises:
        ValueError: bad mode, torque, width, or a position with no cell on the flanks.
    """
    if contact not in ("exact", "smooth"):
        raise ValueError(f"contact = {contact!r}: allowed 'exact', 'smooth'")
    if not torque > 0:
        raise ValueError(f"torque = {torque!r} must be > 0 (N·m)")
    if contact == "smooth" and not width > 0:
        raise ValueError(f"width = {width!r} must be > 0 (m)")
    if mods is None:
        mods = mods_params(None)
    pin, gear = mods["pinion"], mods["gear"]
    g_alpha, pb, b = mesh.path_of_contact, mesh.base_pitch, mesh.face_width
    cos_bb = math.cos(mesh.base_helix_angle)
    force = torque / (mesh.base_radius_pinion * cos_bb)
    dz = b / mesh.n_slices
    z = (np.arange(mesh.n_slices) + 0.5) * dz
    lines = mesh.line_indices()
    # geometry that does not depend on the position
    offset = lines[:, None] * pb - z[None, :] * math.tan(mesh.base_helix_angle)
    zeta = np.broadcast_to(z / b, offset.shape)
    cell_length = dz / cos_bb
    if theta is None:
        theta = _positions(mesh, positions_per_pitch, periods)
    theta = np.asarray(theta, dtype=float)
    n = theta.shape[0]
    te, approach = np.empty(n), np.empty(n)
    stiff, clen, evals = np.empty(n), np.empty(n), np.empty(n, dtype=int)
    lo_s, hi_s = -mesh.extension_span[0], g_alpha + mesh.extension_span[1]
    for j, th in enumerate(theta):
        s = np.mod(mesh.base_radius_pinion * th, pb) + offset
        on = (s >= lo_s) & (s <= hi_s)
        if not on.any():
            raise ValueError(f"no contact cell at theta = {th!r} rad")
        s_on, zeta_on = s[on], zeta[on]
        # beyond the path: the table clamped (the end's stiffness) and the end's deviation
        kl = np.interp(s_on, mesh.stiffness_s, mesh.stiffness_k) * cell_length
        u = np.clip(s_on, 0.0, g_alpha) / g_alpha
        e = _member_deviation(pin, u, zeta_on) + _member_deviation(gear, 1.0 - u, zeta_on)
        e_max = e.max()
        delta0 = e_max - e
        v = None
        if mesh.extended:
            corner_gap, v = _beyond_path(mesh, s_on)
            delta0 = delta0 + corner_gap
        vv = np.ones_like(kl) if v is None else v
        # f(lo) < 0 < f(hi): at hi every cell is compressed by more than V F/Σ V² kl (the margin
        # keeps f(hi) > 0 through rounding when every cell is loaded equally)
        hi = np.max(delta0 / vv) + force / np.dot(vv * vv, kl) * (1.0 + 1e-6)
        if contact == "exact":
            f, args, lo = _residual_exact, (delta0, kl, force, v), 0.0
        else:
            # Σ V kl w softplus((V δ − δ0)/w) <= Σ V kl w exp(V δ/w) < F where every V δ is
            # below the bound (δ < 0: the smallest V the binding one)
            f, args = _residual_smooth, (delta0, kl, force, width, v)
            bound = width * (math.log(force / (np.dot(vv, kl) * width)) - 1.0)
            lo = min(0.0, bound / np.min(vv))
        d, info = brentq(
            f, lo, hi, args=args, xtol=1e-30, rtol=4 * _EPS, maxiter=500, full_output=True
        )
        if not info.converged:
            raise RuntimeError(f"brentq did not converge at theta = {th!r}: {info.flag}")
        gap = vv * d - delta0
        if mesh.extended:  # a corner closed past the extension's end: the extension too short
            end = mesh.extension_gap[:, -1] * cos_bb
            reach = gap + corner_gap
            if np.any((s_on < 0) & (reach > end[0])) or np.any((s_on > g_alpha) & (reach > end[1])):
                raise ValueError(f"a tip corner closes beyond the extension at theta = {th!r}")
        if contact == "exact":
            weight = (gap > 0).astype(float)
        else:  # φ'_w(Δ) = sigmoid(Δ/w)
            weight = 0.5 * (1.0 + np.tanh(0.5 * gap / width))
        te[j] = (d - e_max) / cos_bb
        approach[j] = d
        stiff[j] = np.dot(kl, weight)
        clen[j] = cell_length * weight.sum()
        evals[j] = info.function_calls
    return {
        "theta": theta,
        "te": te,
        "approach": approach,
        "mesh_stiffness": stiff,
        "contact_length": clen,
        "evaluations": evals,
    }


def te_rms(te: np.ndarray) -> float:
    """RMS of a TE curve about its mean (m)."""
    te = np.asarray(te)
    return float(np.sqrt(np.mean((te - te.mean()) ** 2)))
