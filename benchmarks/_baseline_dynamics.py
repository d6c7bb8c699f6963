"""Dynamics baselines and the continuous-time reference (NumPy/SciPy; Numba optional).

Three things on the 1-DOF relative-approach model of a :class:`~jaxgear.dynamics.DynamicModel`

    m ẍ + c ẋ + k_s x + Σ_c k_c(s_c) l_c max(0, x − δ0_c(s_c, z_c)) = F_s,

with s_c(t) the base-plane coordinate of cell c at the pinion angle θ(t) = θ0 + Ω t:

* :func:`reference_response`: the fine reference. The mesh geometry (base pitch, path of contact,
  slices, the k(s) table) and the flank deviations are re-evaluated from the raw numbers of the
  :class:`~jaxgear.MeshModel` and the :class:`~jaxgear.Modifications` (no jaxgear cell table, no
  jaxgear contact solver), so the only thing shared with :func:`jaxgear.dynamics.simulate` is the
  model definition. ``solve_ivp`` (DOP853, rtol 1e-10) segmented at every discontinuity of the
  mesh stiffness (a contact line entering s = 0 or leaving s = g_α, per slice) and at every kink
  (k(s) table nodes, relief starts), with exact quadratic fits of k l and δ0 per piece, and
  restarted at every contact loss or regain of a cell (terminal events on the cell gaps).
* :func:`segmented_response`: the ``solve_ivp`` baseline a careful engineer would write for speed:
  segmented only at the discontinuities (contact lines entering/leaving), a vectorised right-hand
  side (cells of the piece fixed, k(s) and δ0(s) by table lookups, no Python loop over cells),
  LSODA/DOP853/Radau at a chosen tolerance; the kinks (k-table nodes, relief start, contact loss)
  are left to the adaptive step control.
* :func:`numba_newmark_sweep`: Newmark average acceleration with the exact active-set contact loop
  of :func:`jaxgear.solve_contact`, compiled by Numba (``pip install jaxgear[bench]``), on the same
  matrices and cell table as :func:`jaxgear.dynamics.simulate` (identical algorithm: it differs
  from jaxgear by round-off only). Without Numba :func:`numba_available` is False.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from jaxgear import ExactContact

__all__ = [
    "ReferenceModel",
    "numba_available",
    "numba_newmark_sweep",
    "reference_response",
    "segmented_response",
]


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


def _segment_edges(R, bps, roll0, Om, periods: int, T):
    """Times (s) in [0, periods·T] where the mesh crosses a breakpoint ``bps`` (roll distances
    within one base pitch, m): roll0 + r_b1 Ω t = bp + j p_bt, plus the ends; distinct to 1e-12 T.
    The integration is segmented there (no solver steps across a stiffness jump)."""
    j0 = math.floor(roll0 / R.pb)
    times = ((bps[None, :] + np.arange(j0, j0 + periods + 2)[:, None] * R.pb) - roll0) / (
        R.rb1 * Om
    )
    times = times.ravel()
    times = times[(times > 0.0) & (times < periods * T)]
    edges = np.unique(np.concatenate([[0.0], times, [periods * T]]))
    return edges[np.concatenate([[True], np.diff(edges) > 1e-12 * T])]


def reference_response(
    model,
    speed,
    *,
    periods,
    keep_periods=2,
    theta0=0.0,
    rtol=1e-10,
    samples_per_mode=200,
    method="DOP853",
):
    """Integrate ``periods`` mesh periods from the static equilibrium at ``theta0``.

    Returns:
        dict: ``dynamic_factor`` (max mesh force over the last ``keep_periods`` / F_s, the max of
        the continuous solution on a dense grid), ``min_force`` (/F_s), ``periodicity`` (max
        |F(last period) − F(previous)| / F_s on the dense grid), ``pieces`` (solve_ivp calls),
        ``contact_events``, ``time``/``force`` (the kept dense samples: s, /F_s) and
        ``approach`` (the relative approach x (m) there), on the clock of θ = θ0 + Ω t.
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

    edges = _segment_edges(R, bps, roll0, Om, periods, T)

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
    dense_t, dense_f, dense_x = [], [], []
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
                method=method,
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
                dense_x.append(xs)
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
        "approach": np.concatenate(dense_x),
    }


# --------------------------------------------------------------------------------------------
# baseline (a): solve_ivp segmented at the discontinuities, vectorised right-hand side


class SegmentedModel:
    """Set-up of :func:`segmented_response`, built once per model (not timed per speed): the
    reference numbers plus δ0(s) per slice tabulated on a uniform grid along the path of contact
    (linear interpolation by index arithmetic, vectorised over cells and times)."""

    def __init__(self, model, table_points: int = 4097):
        R = self.R = ReferenceModel(model)
        self.s_grid = np.linspace(0.0, R.g, table_points)
        self.ds = self.s_grid[1]
        zeta = R.z / R.b
        self.d0_tab = R.e_ref - R._dev(
            self.s_grid[:, None] / R.g, np.broadcast_to(zeta, (table_points, zeta.size))
        )  # (points, slices)
        ns = R.z.size
        # cell offsets s = roll + offset, line-major like the reference
        self.offset = (R.lines[:, None] * R.pb - R.z[None, :] * R.tanb).ravel()
        self.col = np.tile(np.arange(ns), R.lines.size)

    def force(self, x, roll, cells):
        """Mesh force (N) for approach(es) ``x`` at roll distance(s) ``roll`` (broadcast on a
        trailing cell axis) over the cell indices ``cells``."""
        R = self.R
        s = roll[..., None] + self.offset[cells]
        k = np.interp(s, R.ks_s, R.ks_k)
        u = np.clip(s / self.ds, 0.0, self.s_grid.size - 1.000001)
        i = u.astype(np.intp)
        fr = u - i
        col = self.col[cells]
        d0 = self.d0_tab[i, col] + fr * (self.d0_tab[i + 1, col] - self.d0_tab[i, col])
        return np.sum(k * np.maximum(x[..., None] - d0, 0.0), axis=-1) * R.dl


def segmented_response(
    setup,
    speed,
    *,
    periods,
    keep_periods=2,
    theta0=0.0,
    method="LSODA",
    rtol=1e-6,
    atol=None,
    samples_per_mode=200,
):
    """``solve_ivp`` of the 1-DOF model, one call per piece between two discontinuities of the
    mesh stiffness (contact lines entering or leaving), from the static equilibrium at ``theta0``.

    Args:
        setup: :class:`SegmentedModel` of the model. speed: pinion speed Ω (rad/s).
        method, rtol, atol: ``solve_ivp`` settings on the scaled state (x/x_ref, ẋ/(x_ref ω_n));
            ``atol`` defaults to ``rtol``.
        samples_per_mode: samples of the kept periods per natural period (the dynamic factor is
            the max of the mesh force on them and on the piece ends).

    Returns:
        dict: ``dynamic_factor``, ``nfev``, ``pieces``.
    """
    S, R = setup, setup.R
    atol = rtol if atol is None else atol
    Om = float(speed)
    T = R.pb / (R.rb1 * Om)
    x_ref = R.F / R.kbar
    w = R.omega_n
    roll0 = R.rb1 * theta0
    bps = R.entry_exit()
    edges = _segment_edges(R, bps, roll0, Om, periods, T)
    all_cells = np.arange(S.offset.size)

    def cells_of(a, b):
        mid = roll0 + R.rb1 * Om * 0.5 * (a + b)
        wrap = math.floor(mid / R.pb) * R.pb
        s = mid - wrap + S.offset
        return wrap, all_cells[(s >= 0.0) & (s <= R.g)]

    wrap, cells = cells_of(0.0, edges[1])
    r0 = np.array([roll0 - wrap])

    def f_static(x):
        return float(S.force(np.array([x]), r0, cells)[0]) + R.ks * x - R.F

    hi = x_ref
    while f_static(hi) < 0:
        hi *= 2
    y = np.array([brentq(f_static, -hi, hi, xtol=1e-15 * x_ref, rtol=1e-15) / x_ref, 0.0])
    t_keep = (periods - keep_periods) * T
    n_keep = max(2, math.ceil(keep_periods * T * w / (2 * math.pi) * samples_per_mode))
    grid = np.linspace(t_keep, periods * T, n_keep)
    fmax, nfev = -np.inf, 0
    for a, b in itertools.pairwise(edges):
        wrap, cells = cells_of(a, b)
        rw = roll0 - wrap

        def rhs(t, yy, rw=rw, cells=cells):
            x = yy[0] * x_ref
            v = yy[1] * x_ref * w
            f = S.force(np.array(x), np.array(rw + R.rb1 * Om * t), cells)
            return [yy[1] * w, (R.F - R.c * v - R.ks * x - f) / (R.m * x_ref * w)]

        # samples: the grid, and the piece ends (the force has kinks there, often its maximum)
        sel = grid[(grid > a) & (grid < b)] if b > t_keep else grid[:0]
        t_eval = None
        if b > t_keep:
            t_eval = np.concatenate([[a] if a >= t_keep else [], sel, [b]])
        sol = solve_ivp(
            rhs,
            (a, b),
            y,
            method=method,
            rtol=rtol,
            atol=atol,
            t_eval=t_eval,
            first_step=min(b - a, 0.05 * 2 * math.pi / w),
        )
        if sol.status < 0:
            raise RuntimeError(f"segmented_response: solve_ivp failed: {sol.message}")
        nfev += int(sol.nfev)
        if t_eval is not None:
            fm = S.force(sol.y[0] * x_ref, rw + R.rb1 * Om * sol.t, cells)
            fmax = max(fmax, float(fm.max()))
        y = sol.y[:, -1]  # the state at b (the last t_eval point, or the end of the step)
    return {"dynamic_factor": fmax / R.fs, "nfev": nfev, "pieces": len(edges) - 1}


# --------------------------------------------------------------------------------------------
# baseline (b): Numba Newmark with the exact active-set contact loop


def numba_available() -> bool:
    """Whether Numba can be imported (``pip install jaxgear[bench]``)."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _newmark_speed(M, C, Ks, F, V, kl, d0, mask, X0, Xd0, Xdd0, dt, n_steps, n_keep, max_it):
    """Max mesh force (N) over the last ``n_keep`` of ``n_steps`` Newmark steps (β 1/4, γ 1/2),
    each step an exact contact problem solved by the active set of jaxgear.solve_contact."""
    n = M.shape[0]
    P, c = kl.shape
    b, g = 0.25, 0.5
    a0 = 1.0 / (b * dt * dt)
    a1 = g / (b * dt)
    Keff = a0 * M + a1 * C + Ks
    X, Xd, Xdd = X0.copy(), Xd0.copy(), Xdd0.copy()
    active = np.zeros(c)
    Kt = np.empty((n, n))
    Ft = np.empty(n)
    fmax = -np.inf
    for step in range(n_steps):
        j = (step + 1) % P
        va = a0 * X + Xd / (b * dt) + (0.5 / b - 1.0) * Xdd
        vc = a1 * X + (g / b - 1.0) * Xd + dt * (0.5 * g / b - 1.0) * Xdd
        Feff = F + M @ va + C @ vc
        for q in range(c):
            active[q] = 1.0 if mask[j, q] else 0.0
        x = X
        for _ in range(max_it):
            Kt[:, :] = Keff
            Ft[:] = Feff
            for q in range(c):
                if active[q] > 0.0:
                    wq = kl[j, q]
                    for r in range(n):
                        Ft[r] += wq * d0[j, q] * V[j, q, r]
                        for s in range(n):
                            Kt[r, s] += wq * V[j, q, r] * V[j, q, s]
            if n == 1:
                x = Ft / Kt[0, 0]
            else:
                x = np.linalg.solve(Kt, Ft)
            changed = False
            for q in range(c):
                gap = -d0[j, q]
                for r in range(n):
                    gap += V[j, q, r] * x[r]
                new = 1.0 if (mask[j, q] and gap > 0.0) else 0.0
                if new != active[q]:
                    changed = True
                active[q] = new
            if not changed:
                break
        fm = 0.0
        for q in range(c):
            if mask[j, q]:
                gap = -d0[j, q]
                for r in range(n):
                    gap += V[j, q, r] * x[r]
                if gap > 0.0:
                    fm += kl[j, q] * gap
        Xddn = a0 * (x - X - dt * Xd - dt * dt * (0.5 - b) * Xdd)
        Xd = Xd + dt * ((1.0 - g) * Xdd + g * Xddn)
        X = x.copy()
        Xdd = Xddn
        if step >= n_steps - n_keep and fm > fmax:
            fmax = fm
    return fmax


def _make_sweep(newmark, loop_range):
    def sweep(M, C, Ks, F, V, kl, d0, mask, X0, Xd0, Xdd0, dts, n_steps, n_keep, max_it):
        out = np.empty(dts.size)
        for i in loop_range(dts.size):
            out[i] = newmark(
                M, C, Ks, F, V, kl, d0, mask, X0, Xd0, Xdd0, dts[i], n_steps, n_keep, max_it
            )
        return out

    return sweep


_KERNELS: dict = {}


def _kernels():
    """The Numba-compiled sweeps (serial, and ``parallel=True`` with ``prange`` over speeds),
    compiled lazily on first call."""
    if not _KERNELS:
        import numba

        newmark = numba.njit(_newmark_speed)
        _KERNELS["serial"] = numba.njit(_make_sweep(newmark, range))
        _KERNELS["parallel"] = numba.njit(parallel=True)(_make_sweep(newmark, numba.prange))
    return _KERNELS


def numba_tables(model, steps_per_period: int, max_iterations: int = 100):
    """NumPy arrays of the model matrices, the cell table at ``steps_per_period`` positions and the
    static start (X, Ẋ, Ẍ) (the same as :func:`jaxgear.dynamics.simulate`, exact contact)."""
    from jaxgear.dynamics import mesh_table, static_start

    scene = model.scene
    t = mesh_table(scene, model.mods, int(steps_per_period))
    start = static_start(
        model, contact=ExactContact(max_iterations), steps_per_period=int(steps_per_period)
    )
    X0 = np.asarray(start[0], float)
    M = np.asarray(scene.mass(), float)
    C = np.asarray(model.damping, float)
    Ks = np.asarray(scene.stiffness(), float)
    F = np.asarray(scene.external_load(model.torque), float)
    V = np.ascontiguousarray(np.asarray(t.V, float))
    mask = np.asarray(t.mask, bool)
    kl = np.where(mask, np.asarray(t.k, float) * np.asarray(t.length, float), 0.0)
    d0 = np.asarray(t.delta0, float)
    Xd0 = np.zeros_like(X0)
    gap = V[0] @ X0 - d0[0]
    f = np.where(mask[0], kl[0] * np.maximum(gap, 0.0), 0.0)
    Xdd0 = np.linalg.solve(M, F - C @ Xd0 - Ks @ X0 - V[0].T @ f)
    return (M, C, Ks, F, V, kl, d0, mask, X0, Xd0, Xdd0)


def numba_newmark_sweep(
    model, speeds, *, periods, keep_periods, steps_per_period, kind="serial", tables=None
):
    """Dynamic factor per speed by the Numba Newmark (``kind`` "serial" or "parallel"), every speed
    from the static equilibrium; ``steps_per_period`` per speed (an int or one per speed);
    ``tables``: {N_s: :func:`numba_tables`} built beforehand (else built here).

    Returns:
        (dynamic factors, shape of ``speeds``).
    """
    speeds = np.asarray(speeds, float)
    ns = np.broadcast_to(np.asarray(steps_per_period, int), speeds.shape)
    kernel = _kernels()[kind]
    out = np.empty(speeds.size)
    fs = float(model.static_force)
    angle = float(model.mesh.mesh_period_angle)
    for n in np.unique(ns):
        idx = np.nonzero(ns == n)[0]
        args = tables[int(n)] if tables else numba_tables(model, int(n))
        dts = angle / speeds[idx] / n
        out[idx] = kernel(*args, dts, int(periods) * int(n), int(keep_periods) * int(n), 100) / fs
    return out
