"""Continuous-time reference for the 1-DOF relative-approach model (NumPy/SciPy only).

    m ẍ + c ẋ + k_s x + Σ_c k_c(s_c) l_c max(0, x − δ0_c(s_c, z_c)) = F_s,

with s_c(t) the base-plane coordinate of cell c at the pinion angle θ(t) = θ0 + Ω t. The mesh
geometry (base pitch, path of contact, slices, the k(s) table) and the flank deviations are
re-evaluated here from the raw numbers of the :class:`~jaxgear.MeshModel` and the
:class:`~jaxgear.Modifications` (no jaxgear cell table, no jaxgear contact solver), so the only
thing shared with :func:`jaxgear.dynamics.simulate` is the model definition.

The integration (``scipy.integrate.solve_ivp``, DOP853, rtol 1e-10) is segmented at every
discontinuity of the mesh stiffness (a contact line entering s = 0 or leaving s = g_α, per slice;
for a spur pair at the roll positions 0 and g_α − p_bt of each mesh period), and restarted at
every contact loss or regain of a cell (terminal events on the cell gaps x − δ0_c), so that each
piece is integrated with a smooth right-hand side (up to the kinks of the linear k(s) table and of
a linear relief, which the adaptive step control resolves).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["ReferenceModel", "reference_response"]


def _np(a):
    return np.asarray(a, dtype=float)


def _ramp(x, shape, blend):
    if blend > 0:
        x = blend * np.logaddexp(0.0, x / blend)
    else:
        x = np.maximum(x, 0.0)
    x = np.minimum(x, 1.0)
    return x if shape == "linear" else x * x


def _member_params(mm):
    """The numbers of a MemberModification as Python floats (shapes as strings)."""
    return {
        "te": float(mm.tip_relief_extent),
        "td": float(mm.tip_relief_depth),
        "ts": mm.tip_relief_shape,
        "re": float(mm.root_relief_extent),
        "rd": float(mm.root_relief_depth),
        "rs": getattr(mm, "root_relief_shape", "linear"),
        "blend": float(mm.relief_blend),
        "crown": float(mm.crowning_depth),
        "le": float(mm.end_relief_extent),
        "ed": float(mm.end_relief_depth),
        "slope": float(mm.helix_slope_deviation),
        "proll": _np(mm.profile_deviation_roll),
        "pdev": _np(mm.profile_deviation),
    }


def _member_deviation(q, u, zeta):
    """Normal deviation (m) of one member at roll fraction u and lead fraction zeta."""
    te, re, blend = q["te"], q["re"], q["blend"]
    tip = q["td"] * _ramp((u - (1.0 - te)) / te, q["ts"], blend / te) if q["td"] else 0.0
    root = q["rd"] * _ramp((re - u) / re, q["rs"], blend / re) if q["rd"] else 0.0
    xi = 2.0 * zeta - 1.0
    le = q["le"]
    end = q["ed"] * (
        np.clip((le - zeta) / le, 0.0, 1.0) + np.clip((zeta - (1.0 - le)) / le, 0.0, 1.0)
    )
    prof = np.interp(u, q["proll"], q["pdev"])
    return prof + q["slope"] * (zeta - 0.5) - tip - root - q["crown"] * xi * xi - end


class ReferenceModel:
    """The numbers of a 1-DOF :class:`~jaxgear.dynamics.DynamicModel`, as NumPy floats."""

    def __init__(self, model):
        scene, mesh = model.scene, model.mesh
        if scene.mass().shape != (1, 1):
            raise ValueError("the reference solves the 1-DOF relative-approach model only")
        self.m = float(scene.mass()[0, 0])
        self.c = float(model.damping[0, 0])
        self.ks = float(scene.stiffness()[0, 0])
        self.F = float(scene.external_load(model.torque)[0])
        self.fs = float(model.static_force)
        self.rb1 = float(mesh.base_radius_pinion)
        self.pb = float(mesh.base_pitch)
        self.g = float(mesh.path_of_contact)
        self.tanb = math.tan(float(mesh.base_helix_angle))
        self.cosb = math.cos(float(mesh.base_helix_angle))
        self.b = float(mesh.face_width)
        ns = int(mesh.n_slices)
        self.z = (np.arange(ns) + 0.5) * self.b / ns
        self.dl = self.b / ns / self.cosb  # cell length
        self.lines = np.arange(int(mesh.n_lines), dtype=float) + float(mesh.first_line)
        self.ks_s, self.ks_k = _np(mesh.stiffness_s), _np(mesh.stiffness_k)
        mods = self.mods = model.mods
        qp, qg = _member_params(mods.pinion), _member_params(mods.gear)
        self._dev = lambda u, zeta: (
            _member_deviation(qp, u, zeta) + _member_deviation(qg, 1.0 - u, zeta)
        )
        # e_ref: max over the mesh period of max over the loaded cells of e (a fine position grid)
        rolls = (np.arange(4096) + 0.5) * self.pb / 4096
        s = self._s(rolls[:, None, None])
        mask = (s >= 0.0) & (s <= self.g)
        e = self._dev(s / self.g, np.broadcast_to(self.z / self.b, s.shape))
        self.e_ref = float(np.max(np.where(mask, e, -np.inf)))
        self.kbar = float(model.mesh_stiffness_mean)
        self.omega_n = math.sqrt(self.kbar / self.m)

    def _s(self, roll):
        """s (m) of every cell (line, slice) for a continuous roll distance r_b1 θ − wrap·p_bt."""
        return roll + self.lines[:, None] * self.pb - self.z[None, :] * self.tanb

    def cells(self, roll, mask):
        """(k l, δ0) per cell at roll distance ``roll`` (m) with a fixed cell set ``mask``."""
        s = self._s(roll)
        k = np.interp(s, self.ks_s, self.ks_k)
        d0 = self.e_ref - self._dev(s / self.g, np.broadcast_to(self.z / self.b, s.shape))
        return np.where(mask, k * self.dl, 0.0), d0

    def breakpoints(self):
        """Roll positions in [0, p_bt) where the cell set changes (lines entering/leaving) or
        k(s), δ0(s) have a kink (k-table nodes, relief starts, profile nodes)."""
        zt = self.z * self.tanb
        kinks = [self.ks_s]
        for mm, flip in ((self.mods.pinion, False), (self.mods.gear, True)):
            u = [1.0 - float(mm.tip_relief_extent), float(mm.root_relief_extent)]
            u += list(_np(mm.profile_deviation_roll))
            u = np.array(u)
            kinks.append(self.g * (1.0 - u if flip else u))
        s_k = np.concatenate([[0.0, self.g], *kinks])
        s_k = s_k[(s_k >= 0.0) & (s_k <= self.g)]
        pts = np.mod((s_k[:, None] + zt[None, :]).ravel(), self.pb)
        pts = np.unique(np.round(np.concatenate([[0.0], pts]) / self.pb, 12) % 1.0) * self.pb
        return np.sort(pts)

    def entry_exit(self):
        """Roll positions in [0, p_bt) where a contact line enters (s = 0) or leaves (s = g)."""
        zt = self.z * self.tanb
        pts = np.concatenate([[0.0], np.mod(zt, self.pb), np.mod(self.g + zt, self.pb)])
        return np.sort(np.unique(np.round(pts / self.pb, 12) % 1.0) * self.pb)

    def mesh_force(self, x, roll, mask):
        kl, d0 = self.cells(roll, mask)
        return float(np.sum(kl * np.maximum(x - d0, 0.0)))


def _piece_coefficients(R, wrap_roll, a, b, mask, t_of_roll):
    """Quadratic fits in τ = t − a of k_c l_c and δ0_c over one piece (exact: between the
    breakpoints k(s) is linear and δ0(s) at most quadratic); identical cells are merged."""
    taus = np.array([0.0, 0.5, 1.0]) * (b - a)
    kl, d0 = R.cells(t_of_roll(a + taus)[:, None, None] - wrap_roll, mask)
    kl, d0 = kl[:, mask], d0[:, mask]
    V = np.vander(taus, 3, increasing=True)
    pk = np.linalg.solve(V, kl)  # (3, c): coefficients of 1, τ, τ²
    pd = np.linalg.solve(V, d0)
    # merge cells with the same δ0(τ) (e.g. the slices of a spur pair without lead deviations)
    scale = np.abs(pd).max() + 1e-30
    groups: dict = {}
    inv = np.array(
        [groups.setdefault(tuple(np.round(col / scale, 12)), len(groups)) for col in pd.T]
    )
    n = len(groups)
    pk_m = np.zeros((3, n))
    pd_m = np.zeros((3, n))
    for c in range(inv.size):
        pk_m[:, inv[c]] += pk[:, c]
        pd_m[:, inv[c]] = pd[:, c]
    return pk_m, pd_m


def reference_response(
    model, speed, *, periods, keep_periods=2, theta0=0.0, rtol=1e-10, samples_per_mode=200
):
    """Integrate ``periods`` mesh periods from the static equilibrium at ``theta0``.

    Returns:
        dict: ``dynamic_factor`` (max mesh force over the last ``keep_periods`` / F_s, the max of
        the continuous solution on a dense grid), ``min_force`` (/F_s), ``periodicity`` (max
        |F(last period) − F(previous)| / F_s on the dense grid), ``pieces`` (solve_ivp calls),
        ``contact_events``, ``time``/``force`` (the kept dense samples).
    """
    R = ReferenceModel(model)
    Om = float(speed)
    T = R.pb / (R.rb1 * Om)  # mesh period (s)
    x_ref = R.F / R.kbar
    w = R.omega_n
    bps = R.breakpoints()
    roll0 = R.rb1 * theta0

    def total_roll(t):
        return roll0 + R.rb1 * Om * t

    # breakpoint times: roll0 + r_b1 Ω t = bp + j p_bt
    j0 = math.floor(roll0 / R.pb)
    times = ((bps[None, :] + np.arange(j0, j0 + periods + 2)[:, None] * R.pb) - roll0) / (
        R.rb1 * Om
    )
    times = times.ravel()
    times = times[(times > 0.0) & (times < periods * T)]
    edges = np.unique(np.concatenate([[0.0], times, [periods * T]]))
    edges = edges[np.concatenate([[True], np.diff(edges) > 1e-12 * T])]

    def piece(a, b):
        mid = total_roll(0.5 * (a + b))
        wrap_roll = math.floor(mid / R.pb) * R.pb
        s = R._s(mid - wrap_roll)
        mask = (s >= 0.0) & (s <= R.g)
        return wrap_roll, mask

    # static equilibrium at t = 0
    wrap_roll, mask = piece(0.0, edges[1])

    def f_static(x):
        return R.mesh_force(x, total_roll(0.0) - wrap_roll, mask) + R.ks * x - R.F

    hi = x_ref
    while f_static(hi) < 0:
        hi *= 2
    x0 = brentq(f_static, -hi, hi, xtol=1e-15 * x_ref, rtol=1e-15)
    y = np.array([x0 / x_ref, 0.0])

    t_keep = (periods - keep_periods) * T
    h_mode = 2 * math.pi / w
    dense_t, dense_f = [], []
    n_piece = n_ev = 0
    for a, b in itertools.pairwise(edges):
        wrap_roll, mask = piece(a, b)
        pk, pd = _piece_coefficients(R, wrap_roll, a, b, mask, total_roll)

        def force(x, tau, pk=pk, pd=pd):
            kl = pk[0] + tau * (pk[1] + tau * pk[2])
            d0 = pd[0] + tau * (pd[1] + tau * pd[2])
            return np.sum(kl * np.maximum(x - d0, 0.0), axis=-1)

        def rhs(t, yy, a=a, force=force):
            x = yy[0] * x_ref
            v = yy[1] * x_ref * w
            acc = (R.F - R.c * v - R.ks * x - force(x, t - a)) / R.m
            return [yy[1] * w, acc / (x_ref * w)]

        def make_event(i, a=a, pd=pd):
            def ev(tt, yy):
                tau = tt - a
                return yy[0] - (pd[0, i] + tau * (pd[1, i] + tau * pd[2, i])) / x_ref

            ev.terminal = True
            return ev

        events = [make_event(i) for i in range(pd.shape[1])]
        t = a
        after_event = False
        while t < b - 1e-12 * T:
            # right after a contact event the gap is ~0: a short piece without events first
            t1 = min(b, t + 1e-4 * h_mode) if after_event else b
            sol = solve_ivp(
                rhs,
                (t, t1),
                y,
                method="DOP853",
                rtol=rtol,
                atol=rtol,
                dense_output=True,
                events=None if after_event else events,
                first_step=min(t1 - t, 0.05 * h_mode),
            )
            if sol.status < 0:
                raise RuntimeError(f"reference: solve_ivp failed: {sol.message}")
            after_event = sol.status == 1
            n_ev += int(after_event)
            n_piece += 1
            t_end = float(sol.t[-1])
            if t_end > t_keep:
                n = max(3, math.ceil((t_end - t) / h_mode * samples_per_mode))
                ts = np.linspace(max(t, t_keep), t_end, n)
                xs = sol.sol(ts)[0] * x_ref
                dense_t.append(ts)
                dense_f.append(force(xs[:, None], (ts - a)[:, None]))
            y = sol.y[:, -1]
            t = t_end
    tk = np.concatenate(dense_t)
    fk = np.concatenate(dense_f) / R.fs
    # periodicity: the last period against the previous one on a common grid (offset from the
    # breakpoints: the mesh force jumps where an unmodified tooth pair enters)
    grid = (np.arange(512) + 0.371) * T / 512
    last = np.interp(periods * T - T + grid, tk, fk)
    prev = np.interp(periods * T - 2 * T + grid, tk, fk)
    return {
        "dynamic_factor": float(np.max(fk)),
        "min_force": float(np.min(fk)),
        "periodicity": float(np.max(np.abs(last - prev))),
        "pieces": n_piece,
        "contact_events": n_ev,
        "time": tk,
        "force": fk,
    }
