"""Plausibility of a valid case: one-line :class:`CaseWarning` texts about absurd but valid
inputs (thresholds documented in README.md), from cheap estimates without a contact solve."""

from __future__ import annotations

import math

import numpy as np

from fem_prep import schema as sc

from .._stiffness import SainsotFoundation, sainsot_fit_check
from .._stiffness_models import Weber, stiffness_table
from ..scenes import disc_inertia
from ._case import Case

__all__ = ["MIN_LINE_LOAD_N_PER_MM", "CaseWarning", "mean_static_deflection", "plausibility"]


class CaseWarning(UserWarning):
    """A valid but implausible case (one-line message naming the key): relief far deeper than the
    mean static deflection, a torque too small to deflect the teeth measurably, or a load beyond
    what steel teeth carry, or a gear body outside the range of the Sainsot foundation fit."""


# plausibility thresholds (CaseWarning), documented in README.md
RELIEF_RATIO_WARN = 10.0  # a relief/crowning depth above 10 δ_m
MIN_DEFLECTION_UM = 0.01  # δ_m below 0.01 µm: torque too small
# the torque floor of a case (refused below; the pairs', trains' and planetary stages'): a line
# load F_n/b >= 1e-6 N/mm (δ_m ~ 1e-7 µm; below, round-off)
MIN_LINE_LOAD_N_PER_MM = 1e-6
MAX_LINE_LOAD_N_PER_MM = 2000.0  # F_n / b above what case-hardened steel teeth carry
MAX_DEFLECTION_MODULE = 0.05  # δ_m above 5 % of the normal module
SMOOTH_WIDTH_WARN = 1.0  # CaseWarning: w above δ_m
MAX_DAMPING_RATIO = 1.0  # CaseWarning: Rayleigh ξ above critical at a mesh mode's frequency
MIN_TIP_THICKNESS_MODULE = 0.2  # CaseWarning: a normal tip thickness below 0.2 m_n (thin tip)


def mean_static_deflection(case: Case) -> float:
    """A cheap estimate of the mean static deflection δ_m = F_n / K̄ (m), without a contact solve.

    K̄ is the stiffness model's :meth:`~jaxgear.AbstractStiffness.mean_estimate`: k0 ε_α b /
    cos β_b for ``uniform``, the ISO 6336-1 c_γα b for ``iso6336`` and, for ``weber`` and
    ``fe2d``, c_γα b scaled by E / 210 GPa (the Weber profile of the embedded cases agrees with
    it within about 25 %).

    Raises:
        SchemaError: for ``weber``, when the line load is beyond ``MAX_LINE_LOAD_N_PER_MM`` and the
            stiffness model cannot be evaluated (Hertzian contact wider than the teeth): the
            message names ``[operating] torque_Nm``.
    """
    pair = case.pair
    k_mean = case.stiffness.mean_estimate(pair, case.youngs_modulus)
    w = case.normal_load / pair.face_width * 1e-3
    if case.stiffness.hertz and w > MAX_LINE_LOAD_N_PER_MM:
        try:
            with np.errstate(all="ignore"):
                stiffness_table(  # the Hertzian term of Weber's profile, which fe2d shares
                    pair,
                    Weber(case.stiffness.foundation),
                    youngs_modulus=case.youngs_modulus,
                    poisson_ratio=case.poisson_ratio,
                    line_load=case.nominal_line_load(),
                )
        except (ValueError, ArithmeticError):
            raise sc.SchemaError(
                f"[operating] torque_Nm = {case.torque:.6g}: the line load F_n/b = {w:.6g} N/mm "
                "is far beyond what steel teeth carry (the Hertzian contact would be wider than "
                f"the teeth), allowed up to about {MAX_LINE_LOAD_N_PER_MM:.6g} N/mm"
            ) from None
    return case.normal_load / k_mean


def _mesh_mode_frequencies(case: Case, k_mean: float) -> list[float]:
    """The natural frequencies ω (rad/s) of the torsional modes the mesh excites (a mesh strain
    energy share >= 5 %, as the sweep's critical speeds count them), a cheap estimate without the
    dynamic model: the pinion and gear rotations (the scene's inertias, solid discs by default)
    coupled by the mean mesh stiffness ``k_mean`` (N/m) along V = cos β_b (r_b1, −r_b2), with the
    motor and load rotations on their shafts where a torsional scene has them. For a lumped 3D
    scene, the bearings lower the mesh mode somewhat below this torsional one."""
    spec, pair = case.scene, case.pair
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    motor = spec.model != "lumped3d" and spec.motor_inertia is not None
    load = spec.model != "lumped3d" and spec.load_inertia is not None
    inertias = [spec.motor_inertia] * motor + [i1, i2] + [spec.load_inertia] * load
    n, p = len(inertias), int(motor)
    cb = math.cos(pair.base_helix_angle)
    v = np.zeros(n)
    v[p], v[p + 1] = cb * pair.base_radii[0], -cb * pair.base_radii[1]
    K = k_mean * np.outer(v, v)
    # the shafts motor-pinion and gear-load (stiffness 1 N·m/rad unless given, as the model's)
    for i, k, has in ((0, spec.motor_shaft, motor), (p + 1, spec.load_shaft, load)):
        if has:
            e = np.zeros(n)
            e[i], e[i + 1] = 1.0, -1.0
            K += (k or 1.0) * np.outer(e, e)
    s = 1.0 / np.sqrt(np.asarray(inertias, float))
    w2, U = np.linalg.eigh(s[:, None] * K * s[None, :])
    phi = s[:, None] * U
    elastic = w2 > 1e-9 * w2.max()
    share = k_mean * (v @ phi) ** 2 / np.maximum(np.einsum("ij,ik,kj->j", phi, K, phi), 1e-300)
    keep = elastic & (share >= 0.05)
    return [math.sqrt(w) for w in w2[keep]] or [math.sqrt(w2.max())]


def plausibility(case: Case) -> list[str]:
    """One-line warnings about absurd but valid inputs (thresholds in README.md), those of each
    mesh as a pair case (:meth:`~jaxgear.io.Case.mesh_case`; a pair's: itself), a labelled
    mesh's named (a train's, ``meshes[k] driving-driven: ...``; :func:`_mesh_plausibility`)."""
    out = []
    for k in range(len(case.pairs)):
        label = case.mesh_label(k)
        head = f"meshes[{k}] {label}: " if label else ""
        out.extend(head + text for text in _mesh_plausibility(case.mesh_case(k)))
    return out


def _mesh_plausibility(case: Case) -> list[str]:
    """The warnings of one mesh as a pair case:

    * a relief or crowning depth above ``RELIEF_RATIO_WARN`` (10) × δ_m;
    * δ_m below ``MIN_DEFLECTION_UM`` (0.01 µm): the torque is too small to deflect the teeth;
    * the line load F_n/b above ``MAX_LINE_LOAD_N_PER_MM`` (2000 N/mm) or δ_m above
      ``MAX_DEFLECTION_MODULE`` (5 %) of the normal module: beyond what steel teeth carry;
    * ``foundation = "sainsot"`` on a member whose h_f = r_f/r_int, θ_f give Sainsot coefficients
      outside the span of the published fit (extrapolation);
    * a Rayleigh damping whose ratio ξ = α/(2ω) + β ω/2 exceeds ``MAX_DAMPING_RATIO`` (1) at the
      natural frequency ω of a mode the mesh excites (:func:`_mesh_mode_frequencies`);
    * a normal tip thickness s_an below ``MIN_TIP_THICKNESS_MODULE`` (0.2) m_n (a tip that
      thin chips or hardens through; a pointed one, s_a <= 0, the geometry refuses).

    Raises:
        SchemaError: see :func:`mean_static_deflection`.
    """
    out = []
    delta = mean_static_deflection(case)
    d_um = delta * 1e6
    w = case.normal_load / case.pair.face_width * 1e-3
    t = f"[operating] torque_Nm = {case.torque:.6g}"
    if not math.isfinite(delta):
        return [f"{t}: the mean static deflection is not finite; check the material and torque"]
    if d_um < MIN_DEFLECTION_UM:
        out.append(
            f"{t}: mean static deflection {d_um:.6g} µm is below {MIN_DEFLECTION_UM:g} µm; the "
            "torque is too small for a meaningful transmission error"
        )
    ratio_m = delta / case.pair.normal_module
    if w > MAX_LINE_LOAD_N_PER_MM or ratio_m > MAX_DEFLECTION_MODULE:
        out.append(
            f"{t}: line load F_n/b = {w:.6g} N/mm and mean static deflection {d_um:.6g} µm "
            f"({100 * ratio_m:.3g} % of the module) are beyond what steel teeth carry "
            f"(limits {MAX_LINE_LOAD_N_PER_MM:g} N/mm, {100 * MAX_DEFLECTION_MODULE:g} %)"
        )
    if d_um >= MIN_DEFLECTION_UM and case.smooth_width > SMOOTH_WIDTH_WARN * delta:
        out.append(
            f"[mesh] smooth_width_um = {case.smooth_width * 1e6:.6g}: above the mean static "
            f"deflection {d_um:.6g} µm; the smooth contact law blurs the contact (its TE is offset "
            "by several widths)"
        )
    scene = case.scene
    if scene is not None and scene.damping_model == "rayleigh":
        # the modal damping ratio of C = α M + β K, ξ = α/(2ω) + β ω/2, of each mode the mesh
        # excites, at its natural frequency ω (not at an excitation frequency)
        a, b = scene.rayleigh_alpha, scene.rayleigh_beta
        omegas = _mesh_mode_frequencies(case, case.normal_load / delta)
        xi, w_n = max((a / (2 * w) + b * w / 2, w) for w in omegas)
        if xi > MAX_DAMPING_RATIO:
            key = "beta_s" if b * w_n > a / w_n else "alpha_per_s"
            value = b if key == "beta_s" else a
            out.append(
                f"[scene.damping] {key} = {value:.6g}: the Rayleigh damping ratio at the mesh "
                f"mode's natural frequency ({w_n:.4g} rad/s) is ξ = {xi:.3g} (above critical, "
                f"{MAX_DAMPING_RATIO:g}); usual ξ are 0.01 to 0.1"
            )
    out.extend(_thin_tips(case))
    if d_um >= MIN_DEFLECTION_UM:
        raw = case.raw.get("modifications", {})  # validated: tables (parse_modifications)
        for tag in ("pinion", "gear"):
            mm = getattr(case.modifications, tag)
            own = raw.get(tag, {})
            for key in ("tip_relief", "root_relief", "crowning", "end_relief"):
                depth = float(getattr(mm, f"{key}_depth"))
                if depth > RELIEF_RATIO_WARN * delta:
                    where = f"modifications.{tag}" if key in own else "modifications"
                    out.append(
                        f"[{where}] {key}.depth_um = {depth * 1e6:.6g}: {depth / delta:.3g} × the "
                        f"mean static deflection {d_um:.6g} µm (more than {RELIEF_RATIO_WARN:g} ×); "
                        "the relief removes most of the contact"
                    )
    if case.stiffness == Weber(SainsotFoundation()):
        for tag, fit in zip(("pinion", "gear"), sainsot_fit_check(case.pair)):
            if fit["outside"]:
                bore = (case.pair.pinion, case.pair.gear)[tag == "gear"].bore_radius
                given = "default 0.5 × root radius" if bore is None else "given"
                coeffs = ", ".join(f"{k}* = {fit['coefficients'][k]:.4g}" for k in fit["outside"])
                out.append(
                    f"[{tag}] bore_radius_mm ({given}): h_f = r_f/r_int = {fit['h_f']:.4g}, "
                    f"θ_f = {fit['theta_f']:.4g} rad lie outside the range of the Sainsot fit "
                    f"({coeffs} beyond the fitted span); [mesh] foundation = 'sainsot' extrapolates"
                )
    return list(dict.fromkeys(out))


def _thin_tips(case: Case) -> list[str]:
    """A warning per member whose normal tip thickness s_an = s_at cos β_a (the pair's
    transverse ``tip_thickness``, β_a the helix angle at the tip: tan β_a = tan β r_a/r) is
    below ``MIN_TIP_THICKNESS_MODULE`` m_n. The 0.2 m_n is a common design rule; surface-hardened
    teeth are usually kept at 0.4 m_n or more."""
    pair, out = case.pair, []
    mn, beta = pair.normal_module, pair.helix_angle
    for i, (tag, member) in enumerate((("pinion", pair.pinion), ("gear", pair.gear))):
        beta_a = math.atan(math.tan(beta) * pair.tip_radii[i] / pair.pitch_radii[i])
        s_an = pair.tip_thickness[i] * math.cos(beta_a)
        if s_an < MIN_TIP_THICKNESS_MODULE * mn:
            out.append(
                f"[{tag}] addendum_coeff = {member.addendum_coeff:.6g}, profile_shift = "
                f"{member.profile_shift:.6g}: normal tip thickness {s_an * 1e3:.4g} mm is below "
                f"{MIN_TIP_THICKNESS_MODULE:g} m_n = {MIN_TIP_THICKNESS_MODULE * mn * 1e3:.4g} mm "
                "(a thin tip chips or hardens through; shorten the addendum or lower the shift)"
            )
    return out
