"""An independent continuous-time reference for backlash: a 1-DOF spur pair with a dead-zone mesh
force (NumPy/SciPy only; no jaxgear import).

The model (Kahraman & Singh, J. Sound Vib. 142 (1990) 49-75, eq. (1) with a time-varying
stiffness instead of their constant one): x the flank-normal dynamic transmission error (m),
positive when the drive flanks approach,

    m ẍ + c ẋ + f(x, t) = F,

    f = k_d(t) x            for x > 0             (drive flanks in contact),
        0                   for −j <= x <= 0      (inside the backlash: no contact),
        k_c(t) (x + j)      for x < −j            (coast flanks in contact),

with F = T / r_b1 the static mesh force, j the normal backlash, c a constant viscous damping,
and k_d(t), k_c(t) the stiffness of the tooth pairs in contact on each flank: a per-pair
stiffness k_1 times the number of pairs whose contact point lies on the path of contact. With a
constant stiffness per unit length along the path (the flat k(s) table), the drive flank has two
pairs while the roll position r_b1 θ mod p_bt is below g_α − p_bt and one otherwise; the coast
flank likewise at its roll position (r_b1 (θ_c − θ)) mod p_bt.

Everything here is computed from the gear data by the ISO 21771 formulas written out again
(transverse contact ratio, backlash from the tooth thickness allowances at the operating pitch
circle, the coast flank's phase from the base tooth thickness), not read from jaxgear.

Integration: :func:`scipy.integrate.solve_ivp` (DOP853, rtol 1e-10) segmented at every change
of the stiffness (times known from θ = Ω t) and, inside a segment, restarted at every change of
contact (terminal events x = 0 and x = −j), so that the right-hand side is linear and smooth in
every piece. A sweep continues each speed from the previous speed's end state.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["DeadZonePair", "dead_zone_pair", "response", "sweep"]


def _inv(a: float) -> float:
    return math.tan(a) - a


def _inv_inverse(v: float) -> float:
    a = (3 * v) ** (1 / 3)
    for _ in range(50):
        a -= (math.tan(a) - a - v) / math.tan(a) ** 2
    return a


@dataclasses.dataclass(frozen=True)
class DeadZonePair:
    """The 1-DOF dead-zone model (SI).

    Attributes:
        mass: equivalent mass m (kg). damping: c (N s/m). pair_stiffness: k_1 (N/m).
        force: F (N). backlash: j (m). contact_ratio: ε_α (1 < ε_α < 2).
        pitch_angle: 2π/z1 (rad). coast_phase: θ_c as a fraction of the mesh period.
    """

    mass: float
    damping: float
    pair_stiffness: float
    force: float
    backlash: float
    contact_ratio: float
    pitch_angle: float
    coast_phase: float

    def pairs(self, u):
        """Pairs in contact on (drive, coast) at the mesh-period fraction u = θ z1 / 2π."""
        e = self.contact_ratio - 1.0
        d = np.where(np.mod(u, 1.0) < e, 2, 1)
        c = np.where(np.mod(self.coast_phase - u, 1.0) < e, 2, 1)
        return d, c

    def breakpoints(self) -> np.ndarray:
        """Mesh-period fractions in [0, 1) where a stiffness changes."""
        e = self.contact_ratio - 1.0
        b = {0.0, e % 1.0, self.coast_phase % 1.0, (self.coast_phase - e) % 1.0}
        return np.array(sorted(b))


def dead_zone_pair(
    z1: int,
    z2: int,
    module: float,
    pressure_angle: float,
    allowances: tuple[float, float],
    face_width: float,
    stiffness_per_length: float,
    torque: float,
    inertias: tuple[float, float],
    damping_alpha: float,
    addendum: float = 1.0,
) -> DeadZonePair:
    """The model of a spur pair at the standard centre distance (no profile shift) from its gear
    data: z1, z2, module m (m), pressure angle α (rad), tooth thickness allowances A_sn (m,
    negative thins), face width b (m), stiffness per unit contact length (N/m²), pinion torque T
    (N m), polar inertias (kg m²), c = damping_alpha · m (1/s), addendum h_a* (ISO 21771)."""
    r = (z1 * module / 2, z2 * module / 2)
    rb = tuple(ri * math.cos(pressure_angle) for ri in r)
    ra = tuple(ri + addendum * module for ri in r)
    a = r[0] + r[1]
    # operating angle = α at the standard distance; contact ratio from the tip rolls
    pb = math.pi * module * math.cos(pressure_angle)
    g = (
        math.sqrt(ra[0] ** 2 - rb[0] ** 2)
        + math.sqrt(ra[1] ** 2 - rb[1] ** 2)
        - a * math.sin(pressure_angle)
    )
    eps = g / pb
    # backlash on the pitch circle: p − s1 − s2, s_i = m π/2 + A_i (spur, no shift, α_w = α)
    s = tuple(module * math.pi / 2 + A for A in allowances)
    jt = math.pi * module - s[0] - s[1]
    jn = jt * math.cos(pressure_angle)  # normal to the flanks (spur)
    # the coast contact of the tooth whose drive contact sits at the engagement point (roll
    # ρ_A from T1): the other flank of the same tooth meets the second line of action at roll
    # 2 r_b1 (ψ_b1 + α) − ρ_A from T1' (ψ_b1 = s1/(2 r1) + inv α, the half base thickness),
    # and the gear's coast flank j_bt further on; the contact point taken midway
    rho_a = a * math.sin(pressure_angle) - math.sqrt(ra[1] ** 2 - rb[1] ** 2)
    psi = s[0] / (2 * r[0]) + _inv(pressure_angle)
    roll = 2 * rb[0] * (psi + pressure_angle) - 2 * rho_a + 0.5 * jn
    coast_phase = (roll / pb) % 1.0
    cb = 1.0 / (rb[0] ** 2 / inertias[0] + rb[1] ** 2 / inertias[1])  # m_eq (β = 0)
    return DeadZonePair(
        mass=cb,
        damping=damping_alpha * cb,
        pair_stiffness=stiffness_per_length * face_width,
        force=torque / rb[0],
        backlash=jn,
        contact_ratio=eps,
        pitch_angle=2 * math.pi / z1,
        coast_phase=coast_phase,
    )


def _segment(p: DeadZonePair, t0, t1, y0, kd, kc, out_t):
    """Integrate [t0, t1] with the stiffnesses fixed, restarting at each contact change;
    returns the end state and x at the times ``out_t`` in [t0, t1)."""
    m, c, F, j = p.mass, p.damping, p.force, p.backlash
    xs = np.empty(out_t.size)
    filled = np.zeros(out_t.size, bool)
    t, y = t0, np.array(y0, float)
    impacts = [0, 0]
    for _ in range(1000):
        x = y[0]
        # the contact state, decided by the sign of the gap (and the velocity on a boundary)
        if x > 0 or (x == 0 and y[1] > 0):
            state = 1
        elif x < -j or (x == -j and y[1] < 0):
            state = -1
        else:
            state = 0
        k = kd if state == 1 else (kc if state == -1 else 0.0)
        off = 0.0 if state == 1 else (-j if state == -1 else 0.0)

        def rhs(_, yy, k=k, off=off):
            return [yy[1], (F - c * yy[1] - k * (yy[0] - off)) / m]

        events = []
        if state == 1:
            ev = lambda _, yy: yy[0]
            ev.direction = -1
            events = [ev]
        elif state == -1:
            ev = lambda _, yy: yy[0] + j
            ev.direction = 1
            events = [ev]
        else:
            e1 = lambda _, yy: yy[0]
            e1.direction = 1
            e2 = lambda _, yy: yy[0] + j
            e2.direction = -1
            events = [e1, e2]
        for e in events:
            e.terminal = True
        sel = (out_t >= t) & ~filled
        sol = solve_ivp(
            rhs,
            (t, t1),
            y,
            method="DOP853",
            rtol=1e-10,
            atol=1e-16,
            events=events,
            dense_output=True,
        )
        tend = sol.t[-1]
        sel &= out_t <= tend
        if np.any(sel):
            xs[sel] = sol.sol(out_t[sel])[0]
            filled |= sel
        y = sol.y[:, -1].copy()
        if sol.status == 1:  # an event: snap onto the boundary and carry on
            if state == 0:
                hit = 0 if sol.t_events[0].size else 1
                y[0] = 0.0 if hit == 0 else -j
                impacts[hit] += 1
            else:
                y[0] = 0.0 if state == 1 else -j
                y[1] = y[1] if y[1] != 0 else (-1e-30 if state == 1 else 1e-30)
            t = tend
            continue
        return y, xs, impacts
    raise RuntimeError("too many contact changes in one segment")


def response(
    p: DeadZonePair, speed: float, y0, periods: int = 150, keep: int = 10, samples: int = 256
):
    """Steady-state response at pinion speed Ω (rad/s) from state ``y0`` = (x, ẋ): ``periods``
    mesh periods, the last ``keep`` sampled at ``samples`` points each.

    Returns a dict: ``te_rms`` (RMS of x about its mean, m), ``te_mean`` (m), ``x`` (the kept
    samples), ``coast_share`` and ``drive_loss`` (fractions of the kept samples with x < −j,
    and with x <= 0), ``impacts`` (re-contacts (drive, coast) over the kept periods) and ``end``
    (the final state)."""
    T = p.pitch_angle / speed
    u_bp = p.breakpoints()
    y = np.array(y0, float)
    kept = []
    impacts = np.zeros(2, int)
    for n in range(periods):
        record = n >= periods - keep
        out_t = n * T + (np.arange(samples) / samples) * T if record else np.empty(0)
        xs_all = []
        edges = list(u_bp) + [1.0]
        for a, b in itertools.pairwise(edges):
            if b <= a:
                continue
            d, c = p.pairs(0.5 * (a + b))
            t0, t1 = (n + a) * T, (n + b) * T
            sel = (out_t >= t0) & (out_t < t1)
            y, xs, imp = _segment(
                p, t0, t1, y, d * p.pair_stiffness, c * p.pair_stiffness, out_t[sel]
            )
            xs_all.append(xs)
            if record:
                impacts += imp
        if record:
            kept.append(np.concatenate(xs_all))
    x = np.concatenate(kept)
    return {
        "te_rms": float(np.sqrt(np.mean((x - x.mean()) ** 2))),
        "te_mean": float(x.mean()),
        "x": x,
        "coast_share": float(np.mean(x < -p.backlash)),
        "drive_loss": float(np.mean(x <= 0)),
        "impacts": impacts.tolist(),
        "end": y,
    }


def sweep(p: DeadZonePair, speeds, y0, periods: int = 150, keep: int = 10) -> list[dict]:
    """:func:`response` at each speed in order, each from the previous one's end state."""
    out, y = [], np.array(y0, float)
    for s in speeds:
        r = response(p, float(s), y, periods, keep)
        out.append({k: v for k, v in r.items() if k != "x"})
        y = r["end"]
    return out
