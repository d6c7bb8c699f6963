"""The continuous refinement of a sizing's candidates: for each discrete (m_n, z1, z2) the helix
angle, the profile shifts (with a fixed centre distance only x1: the sum follows from it, ISO
21771) and the face width solved by a constrained optimisation through the rating's gradients
(:func:`refine`), batched over the candidates.

Method: an augmented Lagrangian (Powell-Hestenes-Rockafellar, inequality form) outer loop of a
fixed number of iterations around ``optimistix.BFGS`` inner minimisations, the whole loop under
``jax.vmap`` over the candidates (one compiled program per chunk size, objective and spec
shape). The bounds of each variable are kept by a smooth map of an unbounded one,
v = lo + (hi − lo)(1 + sin y)/2; the validity checks of :data:`jaxgear.sizing.CHECKS` (their
continuous margins, scaled by m_n or by the minimum safety factors) and the spec's limits are
the inequality constraints, each held at least :data:`MARGIN` inside. Each candidate is solved
from its enumerated design and from the further :data:`STARTS` (local optima). Every optimum is
re-rated by the sizing's own candidate function and its own checks: one that fails any (or is
worse than the enumerated design) is not reported; the row keeps its enumerated design.
"""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from .._geometry import involute
from ._candidates import Candidates, enumerate_candidates
from ._size import OUTPUTS, SizingTable, _one, _static, _table, program_arguments, size
from ._spec import SizingSpec

__all__ = ["MARGIN", "REFINE_OBJECTIVES", "STARTS", "TOLERANCE", "refine"]

#: what the refinement can optimise: name → what it asks
REFINE_OBJECTIVES = {
    "mass": "the least blank mass (both gears) meeting every limit",
    "margin": "the largest least safety margin min(S_H/S_Hmin, S_F/S_Fmin, S_B/S_Bmin) meeting "
              "every limit, at no more than the enumerated design's blank mass",
}
#: how far inside each (scaled) constraint the optimiser aims: g >= MARGIN, g a margin over m_n
#: or a safety factor's S/S_min − 1
MARGIN = 1e-4
#: the largest scaled violation of g >= MARGIN at a converged optimum (the reported design must
#: in any case pass every check exactly)
TOLERANCE = 1e-5
#: the further starts of each candidate's solve (the problem has local optima: β against the
#: shifts), as fractions of the ranges of (β, x1, x2); the face width starts as enumerated
STARTS = ((0.25, 0.25, 0.75), (0.75, 0.75, 0.25), (0.25, 0.75, 0.25), (0.75, 0.25, 0.75),
          (0.9, 0.1, 0.5), (0.1, 0.9, 0.5), (0.9, 0.5, 0.9), (0.5, 0.1, 0.1))
#: a large stand-in (m, or dimensionless) for a limit the spec does not set
_FREE = 1e3
#: the inner minimisations' relative tolerance (optimistix's Cauchy test on y and f)
_RTOL = 1e-8
#: how BFGS takes the Lagrangian's gradient (optimistix's ``autodiff_mode``): reverse mode; the
#: forward mode (five variables) compiles no faster (docs/sizing.md, "Refining the continuous
#: variables", its cost)
_AUTODIFF_MODE = "bwd"


def _shift_sum(m, z1, z2, an, beta, a):
    """The sum x1 + x2 whose zero-backlash centre distance is ``a`` (ISO 21771), and
    cos α_wt (< 1 where ``a`` is reachable)."""
    at = jnp.arctan(jnp.tan(an) / jnp.cos(beta))
    cos_awt = (z1 + z2) * m / jnp.cos(beta) * jnp.cos(at) / (2 * a)
    awt = jnp.arccos(jnp.clip(cos_awt, -1.0, 1.0 - 1e-12))
    return (involute(awt) - involute(at)) * (z1 + z2) / (2 * jnp.tan(an)), cos_awt


def _design(y, p, an, fixed):
    """The design (β, x1, x2, b) of the unbounded variables ``y`` (4,) of candidate ``p``."""
    v = p["lo"] + (p["hi"] - p["lo"]) * (1 + jnp.sin(y[:4])) / 2
    beta, x1, x2, b = v
    if fixed:
        x2 = _shift_sum(p["m"], p["z1"], p["z2"], an, beta, p["lim"][2])[0] - x1
    return beta, x1, x2, b


def _evaluate(y, p, static, settings, operating, scuffing, fixed, objective):
    """(objective, constraints g (>= 0 where met, scaled), outputs) of ``y`` (the unbounded
    variables, (5,): β, x1, x2, b mapped into their bounds, and the margin objective's t)."""
    return _evaluate_design(_design(y, p, static[0], fixed), y[4], p, static, settings,
                            operating, scuffing, fixed, objective)


def _evaluate_design(design, t, p, static, settings, operating, scuffing, fixed, objective):
    """(objective, constraints g (>= 0 where met, scaled), outputs) of the design (β, x1, x2,
    b) (x2 unread with a fixed centre distance: it follows) and ``t`` (the margin objective's
    epigraph variable)."""
    an = static[0]
    beta, x1, x2, b = design
    m = p["m"]
    if fixed:
        x2 = _shift_sum(m, p["z1"], p["z2"], an, beta, p["lim"][2])[0] - x1
    c = {"m": m, "z1": p["z1"], "z2": p["z2"], "x1": x1, "x2": x2, "b": b}
    o, _, mg = _one(c, (an, beta) + tuple(static[2:]), settings, operating, margins=True,
                    scuffing=scuffing)
    out = dict(zip(OUTPUTS, o, strict=True))
    d1, d2, da = out["reference_diameter_1_m"], out["reference_diameter_2_m"], o[2:4]
    ea, eb = out["eps_alpha"], out["eps_beta"]
    s_h, s_f = o[18:20] / settings.min_safety_pitting, o[20:22] / settings.min_safety_bending
    if scuffing is not None:  # S_B/S_Bmin beside the gears' S_F/S_Fmin (its constraint too)
        s_f = jnp.concatenate([s_f, (out["S_B"] / scuffing.min_safety)[None]])
    lim = p["lim"]  # b/d1 max, D max, a min, a max, sum lo, sum hi, x lo, x hi
    a = mg["centre_distance"]
    if fixed:
        total, cos_awt = _shift_sum(m, p["z1"], p["z2"], an, beta, lim[2])
        centre = jnp.stack([total - lim[4], lim[5] - total, 1.0 - 1e-9 - cos_awt])
        shift = jnp.stack([x2 - lim[6], lim[7] - x2])
    else:
        centre = jnp.stack([(a - lim[2]) / m, (lim[3] - a) / m, jnp.ones(())])
        shift = jnp.ones(2)
    g = [mg["root"] / m, mg["tip"] / m, mg["tip_thickness"] / m, mg["undercut"] / m,
         mg["interference"] / m, mg["tip_root_clearance"] / m, jnp.stack([ea, ea + eb - 1.0]),
         (jnp.stack([d1, d2]) - 5e-3) / m, s_h - 1.0, s_f - 1.0, (lim[1] - da) / m,
         ((lim[0] * d1 - b) / m)[None], centre, shift]
    mass = out["mass_kg"] / p["mass0"]
    if objective == "mass":
        f = mass
    else:  # the epigraph of the least margin: maximise t <= every S/S_min, mass <= mass0
        g += [jnp.concatenate([s_h, s_f]) - t, (1.0 - mass)[None]]
        f = -t
    return f, jnp.concatenate([jnp.ravel(v) for v in g]), out


def _solve_one(p, static, settings, operating, scuffing, fixed, objective, outer, inner):
    """One candidate's augmented-Lagrangian solve from its start ``p["y0"]``: the variables,
    whether it converged, the largest scaled violation of the constraints (g >= 0)."""

    def fg(y):
        f, g, _ = _evaluate(y, p, static, settings, operating, scuffing, fixed, objective)
        return f, g

    def lagrangian(y, args):
        lam, rho = args
        f, g = fg(y)
        h = jnp.maximum(0.0, lam - rho * (g - MARGIN))
        return f + (jnp.sum(h**2) - jnp.sum(lam**2)) / (2 * rho)

    solver = optx.BFGS(rtol=_RTOL, atol=_RTOL * 1e-2)
    # one evaluation a step (the compiled program's size): f, g carried from it
    shape = jax.eval_shape(fg, p["y0"])[1]
    big = jnp.asarray(1e9)

    def step(carry, _):
        y, f, g, lam, rho, viol_prev, _ok = carry
        sol = optx.minimise(lagrangian, solver, y, (lam, rho), max_steps=inner, throw=False,
                            options={"autodiff_mode": _AUTODIFF_MODE})
        f_new, g_new = fg(sol.value)
        finite = (jnp.isfinite(f_new) & jnp.all(jnp.isfinite(g_new))
                  & jnp.all(jnp.isfinite(sol.value)))
        steady = jnp.abs(f_new - f) <= 1e-9 * (1.0 + jnp.abs(f_new))
        y = jnp.where(finite, sol.value, y)
        f, g = jnp.where(finite, f_new, f), jnp.where(finite, g_new, g)
        lam = jnp.where(finite, jnp.maximum(0.0, lam - rho * (g - MARGIN)), lam)
        viol = jnp.max(jnp.maximum(0.0, MARGIN - g))
        rho = jnp.where(viol > 0.25 * viol_prev, jnp.minimum(10.0 * rho, 1e9), rho)
        ok = finite & steady & (sol.result == optx.RESULTS.successful)
        return (y, f, g, lam, rho, viol, ok), None

    carry = (p["y0"], big, jnp.full(shape.shape, -big), jnp.zeros(shape.shape),
             jnp.asarray(10.0), big, jnp.asarray(False))
    (y, _, g, _, _, viol, ok), _ = jax.lax.scan(step, carry, None, length=outer)
    beta, x1, x2, b = _design(y, p, static[0], fixed)
    converged = ok & (viol <= TOLERANCE)
    return jnp.stack([beta, x1, x2, b]), converged, jnp.max(jnp.maximum(0.0, -g))


@eqx.filter_jit
def _solve(batch, static, settings, operating, scuffing, fixed, objective, outer, inner):
    return jax.vmap(lambda p: _solve_one(p, static, settings, operating, scuffing, fixed,
                                         objective, outer, inner))(batch)


@eqx.filter_jit
def _rate(batch, static, settings, operating, scuffing):
    """The sizing's candidate function (:func:`_one`) of designs with their own β."""
    def one(c):
        o, passed, mg = _one(c, (static[0], c["beta"]) + tuple(static[2:]), settings,
                             operating, margins=True, scuffing=scuffing)
        return o, passed, mg["centre_distance"]
    return jax.vmap(one)(batch)


def _limits(spec: SizingSpec) -> np.ndarray:
    """The spec's limits the constraints read (a stand-in where unset): (b/d1)_max, D_max,
    a_min, a_max, shift sum lo, hi, shift lo, hi."""
    a = spec.centre_distance or (0.0, _FREE)
    xr = spec.profile_shift_range or (-_FREE, _FREE)
    return np.array([
        _FREE if spec.face_width_ratio is None else spec.face_width_ratio,
        _FREE if spec.outer_diameter_max is None else spec.outer_diameter_max,
        a[0], a[1], *spec.profile_shift_sum, *xr], dtype=float)


def _bounds(spec: SizingSpec, cands: Candidates) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) of (β, x1, x2, b) per candidate (n, 4): a fixed variable has lo == hi."""
    n = len(cands)
    beta = spec.helix_angle_range or (spec.helix_angle, spec.helix_angle)
    lo = np.stack([np.full(n, beta[0]), cands.x1, cands.x2, np.full(n, spec.face_width[0])], 1)
    hi = np.stack([np.full(n, beta[1]), cands.x1, cands.x2, np.full(n, spec.face_width[1])], 1)
    if spec.profile_shift_range is not None:
        lo[:, 1:3], hi[:, 1:3] = spec.profile_shift_range
    return lo, hi


def _start(v0, lo, hi):
    """The unbounded variables of the designs ``v0`` (n, 4) (kept off the bounds, where the
    map's slope vanishes)."""
    span = hi - lo
    u = np.where(span > 0, 2 * (v0 - lo) / np.where(span > 0, span, 1.0) - 1, 0.0)
    return np.arcsin(np.clip(u, -0.95, 0.95))


def refine(spec: SizingSpec, table: SizingTable | None = None, *, rows=None,
           objective: str | None = None, outer: int = 12, inner: int = 40, chunk: int = 64,
           starts: int = len(STARTS) + 1,
           progress: Callable[[int, int], None] | None = None) -> SizingTable:
    """Refine the continuous variables of ``spec``'s candidates: the helix angle within
    ``spec.helix_angle_range``, the profile shifts within ``spec.profile_shift_range`` (x1
    alone with a fixed centre distance: x2 = (x1 + x2) − x1, the sum from the centre distance
    and β, ISO 21771) and the face width within ``spec.face_width`` (and b <= (b/d1)_max d1),
    each candidate from its enumerated design (feasible or not), by an augmented Lagrangian
    around ``optimistix.BFGS`` through the rating's gradients (module docstring), batched.

    Constraints (each the continuous margin of a check of :data:`jaxgear.sizing.CHECKS`): root
    and tip diameters, normal tip thickness >= tip_thickness_min · m_n, no undercut (form roll
    >= 0), no interference, tip/root clearance, ε_α > 0 and ε_γ >= 1, d >= 5 mm, S_H >= S_Hmin
    and S_F >= S_Fmin on both gears, S_B >= S_Bmin with ``spec.scuffing`` (ISO/TS 6336-20's
    closed form), the outer diameter, b/d1, the centre-distance window (a fixed one: the shift
    sum within ``spec.profile_shift_sum``, x2 within the shift range).

    A refined design is reported only where it passes every check of the table (re-rated by
    :func:`jaxgear.sizing.candidate_outputs`' function, the numbers ``--write`` writes) and the
    ranges, and the enumerated design fails some check or is no better in the objective;
    otherwise the row keeps its enumerated design.

    Args:
        spec: the :class:`SizingSpec` (its ranges and ``refine_objective``).
        table: its :func:`jaxgear.sizing.size` table (computed if None).
        rows: the rows to refine (an index array; None: every row).
        objective: a key of :data:`REFINE_OBJECTIVES`, or None: ``spec.refine_objective``.
        outer: the augmented-Lagrangian iterations (fixed). inner: the most BFGS steps each.
        chunk: solves per call of the compiled program (the last padded).
        starts: the solves of each candidate: from its enumerated design, then from the
            first ``starts`` − 1 points of :data:`STARTS`; the best design that passes every
            check is reported (1 to ``len(STARTS) + 1``).
        progress: called as ``progress(done, total)`` after each chunk, or None.

    Returns:
        :class:`SizingTable` of the same rows: the refined rows' ``x1``, ``x2``,
        ``face_width_m``, ``centre_distance_m`` and every output replaced, and the columns
        ``helix_angle_rad`` (β of the row), ``refined`` (1 where the row holds a refined
        design), ``refine_converged`` (1 where the solve converged: inner minimisations
        successful, objective steady, violation <= :data:`TOLERANCE`) and
        ``refine_violation`` (the largest scaled violation of g >= 0 at the solve's optimum,
        0 where met; NaN for rows not refined).

    Raises:
        ValueError: an argument out of range (one line naming it).
    """
    objective = spec.refine_objective if objective is None else objective
    if objective not in REFINE_OBJECTIVES:
        raise ValueError(f"refine: objective = {objective!r} is out of range: allowed "
                         f"{', '.join(map(repr, REFINE_OBJECTIVES))}")
    for name, v, top in (("outer", outer, None), ("inner", inner, None), ("chunk", chunk, None),
                         ("starts", starts, len(STARTS) + 1)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1 or (top and v > top):
            raise ValueError(f"refine: {name} = {v!r} is out of range: allowed an integer >= 1"
                             + (f" and <= {top}" if top else ""))
    cands = enumerate_candidates(spec)
    n = len(cands)
    rows = np.arange(n) if rows is None else np.asarray(rows, dtype=int).reshape(-1)
    if rows.size and not (rows.min() >= 0 and rows.max() < n):
        raise ValueError(f"refine: rows out of range: allowed 0 … {n - 1} (the spec's "
                         "candidates)")
    if table is None:
        table = size(spec)
    if len(table) != n:
        raise ValueError(f"refine: table of {len(table)} rows is out of range: allowed the "
                         f"spec's table ({n} rows)")
    fixed = spec.fixed_centre_distance
    static = _static(spec)
    settings, operating, scuffing = program_arguments(spec)
    lo, hi = _bounds(spec, cands)
    v0 = np.stack([np.full(n, spec.helix_angle), cands.x1, cands.x2, cands.face_width], 1)
    margin0 = np.nan_to_num(table.columns["least_margin"], nan=0.0)[:, None]
    mass0 = table.columns["mass_kg"]
    y0 = [np.concatenate([_start(v0, lo, hi), margin0], 1)]
    for frac in STARTS[: starts - 1]:
        v = np.concatenate([lo[:, :3] + np.asarray(frac) * (hi[:, :3] - lo[:, :3]), v0[:, 3:]], 1)
        y0.append(np.concatenate([_start(v, lo, hi), margin0], 1))
    y0 = np.stack(y0, 1)  # (n, starts, 5)
    fields = {"m": cands.normal_module, "z1": cands.z1.astype(float),
              "z2": cands.z2.astype(float), "lo": lo, "hi": hi,
              "mass0": np.where(np.isfinite(mass0) & (mass0 > 0), mass0, 1.0),
              "lim": np.broadcast_to(_limits(spec), (n, 8))}
    # every (row, start) a solve of the batch, row-major
    who, which = np.repeat(rows, starts), np.tile(np.arange(starts), rows.size)
    fields = {name: v[who] for name, v in fields.items()} | {"y0": y0[who, which]}
    k = who.size
    design, conv, viol = np.zeros((k, 4)), np.zeros(k, bool), np.zeros(k)
    for start in range(0, k, chunk):
        stop = min(start + chunk, k)
        idx = np.r_[np.arange(start, stop), np.full(chunk - (stop - start), stop - 1)]
        batch = {name: jnp.asarray(v[idx], dtype=float) for name, v in fields.items()}
        d, c, e = _solve(batch, static, settings, operating, scuffing, fixed, objective, outer,
                         inner)
        design[start:stop] = np.asarray(d)[: stop - start]
        conv[start:stop] = np.asarray(c)[: stop - start]
        viol[start:stop] = np.asarray(e)[: stop - start]
        if progress is not None:
            progress(stop // starts, rows.size)
    return _merge(spec, table, cands, rows, starts, design, conv, viol, objective, static,
                  (settings, operating, scuffing), chunk)


def _merge(spec, table, cands, rows, starts, design, conv, viol, objective, static,
           args, chunk) -> SizingTable:
    """The table with each row's best refined design (of its starts) that passes every check
    (and beats or replaces an infeasible enumerated one), re-rated; the refinement's
    columns (of the reported solve; of the least violation where none passes)."""
    n = len(cands)
    cols = {name: np.array(v, copy=True) for name, v in table.columns.items()}
    failed = np.array(table.failed, copy=True)
    refined, converged, violation = np.zeros(n, int), np.zeros(n, int), np.full(n, np.nan)
    k = design.shape[0]
    if k:
        who = np.repeat(rows, starts)
        m, z1, z2 = cands.normal_module[who], cands.z1[who], cands.z2[who]
        batch = {"m": m, "z1": z1.astype(float), "z2": z2.astype(float), "beta": design[:, 0],
                 "x1": design[:, 1], "x2": design[:, 2], "b": design[:, 3]}
        o, passed, a = [], [], []
        for start in range(0, k, chunk):  # the chunks of the solve (one compiled shape)
            stop = min(start + chunk, k)
            pad = np.r_[np.arange(start, stop), np.full(chunk - (stop - start), stop - 1)]
            r = _rate({kk: jnp.asarray(v[pad], dtype=float) for kk, v in batch.items()},
                      static, *args)
            for acc, v in zip((o, passed, a), r, strict=True):
                acc.append(np.asarray(v)[: stop - start])
        o, passed, a = (np.concatenate(v) for v in (o, passed, a))
        if spec.fixed_centre_distance:  # the window's own value: the design reaches it
            a = np.full(k, spec.centre_distance[0])
        new = Candidates(m, z1, z2, design[:, 1], design[:, 2], design[:, 3], a)
        t = _table(spec, new, o, passed, helix_angle=design[:, 0])
        ok = t.feasible & _in_ranges(spec, new, design[:, 0], t.columns["reference_diameter_1_m"])
        score = t.columns["mass_kg"] if objective == "mass" else -t.columns["least_margin"]
        score = np.where(ok, score, np.inf).reshape(-1, starts)
        best = np.where(np.isfinite(score).any(axis=1), np.argmin(score, axis=1),
                        np.argmin(viol.reshape(-1, starts), axis=1))
        pick = np.arange(rows.size) * starts + best
        converged[rows], violation[rows] = conv[pick].astype(int), viol[pick]
        if objective == "mass":
            better = t.columns["mass_kg"][pick] <= table.columns["mass_kg"][rows]
        else:
            better = t.columns["least_margin"][pick] >= table.columns["least_margin"][rows]
        take = ok[pick] & (better | ~table.feasible[rows])
        src = pick[take]
        for name, v in t.columns.items():
            cols[name][rows[take]] = v[src]
        failed[rows[take]] = t.failed[src]
        refined[rows[take]] = 1
    cols |= {"refined": refined, "refine_converged": converged, "refine_violation": violation}
    return SizingTable(cols, failed)


def _in_ranges(spec: SizingSpec, c: Candidates, beta, d1) -> np.ndarray:
    """Whether each refined design lies in the spec's ranges that the table's checks do not
    read: β, the shifts, b/d1, the centre-distance window (a fixed one: the shift sum)."""
    tol = 1e-12
    ok = np.ones(len(c), bool)
    if spec.helix_angle_range is not None:
        lo, hi = spec.helix_angle_range
        ok &= (beta >= lo - tol) & (beta <= hi + tol)
    if spec.profile_shift_range is not None:
        lo, hi = spec.profile_shift_range
        ok &= (c.x1 >= lo - tol) & (c.x1 <= hi + tol) & (c.x2 >= lo - tol) & (c.x2 <= hi + tol)
    ok &= c.face_width <= spec.face_width[1] * (1 + tol)
    if spec.face_width_ratio is not None:
        ok &= c.face_width <= spec.face_width_ratio * d1 * (1 + tol)
    if spec.centre_distance is not None:
        if spec.fixed_centre_distance:
            total = c.x1 + c.x2
            ok &= (total >= spec.profile_shift_sum[0] - tol) & (total <= spec.profile_shift_sum[1] + tol)
        else:
            ok &= (c.centre_distance >= spec.centre_distance[0] * (1 - tol)) & (
                c.centre_distance <= spec.centre_distance[1] * (1 + tol))
    return ok & np.isfinite(beta)
