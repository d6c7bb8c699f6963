"""Load factors of the ISO 6336 rating, ISO 6336-1:2019: K_v (clause 6, method B), K_Hβ and
K_Fβ (clause 7), K_Hα and K_Fα (clause 8, method B), with c' and c_γα of method B (clause 9);
a factor given in :class:`jaxgear.rating.GivenFactors` replaces the computed one. And K_Hβ and K_Hα
measured on a jaxgear load distribution (:func:`face_load_factor`,
:func:`transverse_load_factor`). Pure ``jax.numpy`` functions of the
:class:`jaxgear.rating.RatingGeometry`, the operating point and the settings."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array

from .._util import as_float, check_real

__all__ = [
    "LoadFactors",
    "face_load_factor",
    "iso6336_load_factors",
    "transverse_factor_limits",
    "transverse_load_factor",
]

E_STEEL = 206e9  # Pa: ISO 6336-1's reference modulus of c'_th
ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
LOW_LOAD = 1e5  # N/m = 100 N/mm


class LoadFactors(eqx.Module):
    """K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα (scalars) and ``sources`` (static: symbol → "given" or
    "ISO 6336-1 method B"), with the intermediate values of their clauses (``details``, SI,
    method B's whether or not the factor is given): K_v's ``resonance_ratio_N``,
    ``resonance_ratio_N_S``, ``reduced_mass_kg_per_m``, ``C_a_m`` (tip relief), ``f_pb_eff_m``,
    ``f_falpha_eff_m`` (less running-in), ``B_p``, ``B_f``, ``B_k``; K_Hβ's ``F_m_per_b_N_per_m``,
    ``F_betax_m``, ``F_betay_m``, ``c_gamma_beta_N_per_m2``; ``c_prime_N_per_m2``,
    ``c_gamma_alpha_N_per_m2`` (clause 9) and K_Fβ's exponent ``N_F`` (``rating.md`` prints
    them)."""

    K_A: Array
    K_v: Array
    K_Hbeta: Array
    K_Fbeta: Array
    K_Halpha: Array
    K_Falpha: Array
    details: dict
    sources: dict = eqx.field(static=True)


def _tangential_load(g, operating):
    """F_t = 2 T₁/d₁ (N) at the reference circle; ``g`` the derived geometry."""
    return 2 * operating.torque / g.reference_diameter[0]


def _stiffness(geometry, g, settings, specific_load):
    """c' and c_γα (N/m per m of face width), ISO 6336-1 method B (9.3), C_R = 1 (solid)."""
    beta = geometry.helix_angle
    zn = geometry.stiffness_teeth(g)
    x1, x2 = geometry.profile_shift[0], geometry.profile_shift[1]
    c = ISO_C
    q = (
        c[0]
        + c[1] / zn[0]
        + c[2] / zn[1]
        + c[3] * x1
        + c[4] * x1 / zn[0]
        + c[5] * x2
        + c[6] * x2 / zn[1]
        + c[7] * x1**2
        + c[8] * x2**2
    )
    an_deg = geometry.normal_pressure_angle * 180 / jnp.pi
    cb = jnp.mean((1 + 0.5 * (1.2 - geometry.dedendum_coeff)) * (1 - 0.02 * (20.0 - an_deg)))
    e = settings.material.youngs_modulus
    low = jnp.minimum(specific_load / LOW_LOAD, 1.0) ** 0.25
    c1 = 1e9 / q * 0.8 * cb * jnp.cos(beta) * e / E_STEEL * low
    return c1, c1 * (0.75 * g.transverse_contact_ratio + 0.25)


def _dynamic_factor(geometry, g, operating, settings, stiffness, line_load):
    """K_v, ISO 6336-1 clause 6 (method B): the resonance ratio N = ω₁/ω_E1 with ω_E1 =
    √(c_γα/m_red)/z₁ and m_red of two solid blanks, and the regions of N."""
    c1, cga = stiffness
    mat, acc, tr = settings.material, settings.accuracy, settings.material.treatment
    dm = (g.tip_diameter + g.root_diameter) / 2
    m_star = jnp.pi / 8 * mat.density * dm**4 / g.base_diameter**2
    m_red = geometry.reduced_mass(m_star)
    n_ratio = operating.speed / (jnp.sqrt(cga / m_red) / geometry.teeth[0])
    sh = jnp.min(mat.sigma_h_lim)
    f_pb = acc.base_pitch - tr.running_in_alpha(acc.base_pitch, sh)
    f_fa = acc.profile_form - tr.running_in_alpha(acc.profile_form, sh)
    if settings.tip_relief is None:
        ca = settings.running_in_tip_relief()
    else:
        ca = settings.tip_relief
    bp, bf = c1 * f_pb / line_load, c1 * f_fa / line_load
    bk = jnp.abs(1 - c1 * ca / line_load)
    eg = g.transverse_contact_ratio + g.overlap_ratio
    big = eg > 2
    cv1, cv5 = 0.32, 0.47
    cv2 = jnp.where(big, 0.57 / (eg - 0.3), 0.34)
    cv3 = jnp.where(big, 0.096 / (eg - 1.56), 0.23)
    cv4 = jnp.where(big, (0.57 - 0.05 * eg) / (eg - 1.44), 0.90)
    cv6 = jnp.where(big, 0.12 / (eg - 1.74), 0.47)
    cv7 = jnp.where(
        eg <= 1.5, 0.75, jnp.where(eg <= 2.5, 0.125 * jnp.sin(jnp.pi * (eg - 2)) + 0.875, 1.0)
    )
    n_s = jnp.where(line_load < LOW_LOAD, 0.5 + 0.35 * jnp.sqrt(line_load / LOW_LOAD), 0.85)
    sub = n_ratio * (cv1 * bp + cv2 * bf + cv3 * bk) + 1
    main = cv1 * bp + cv2 * bf + cv4 * bk + 1
    super_ = cv5 * bp + cv6 * bf + cv7
    inter = super_ + (main - super_) * (1.5 - n_ratio) / 0.35
    kv = jnp.where(
        n_ratio <= n_s,
        sub,
        jnp.where(n_ratio <= 1.15, main, jnp.where(n_ratio < 1.5, inter, super_)),
    )
    return kv, {
        "resonance_ratio_N": n_ratio,
        "resonance_ratio_N_S": n_s,
        "reduced_mass_kg_per_m": m_red,
        "C_a_m": ca,
        "f_pb_eff_m": f_pb,
        "f_falpha_eff_m": f_fa,
        "B_p": bp,
        "B_f": bf,
        "B_k": bk,
    }


def helix_modification_factor(settings) -> Array:
    """B₂ of ISO 6336-1 clause 7's initial mesh misalignment F_βx = 1.33 B₁ f_sh + B₂ f_ma
    (here f_sh = 0, f_ma = f_Hβ): 0.5 for a lead crowning C_β (``settings.crowning``) at
    least f_Hβ/2 deep (the depth the standard's crowning offsets: C_β ≈ F_βx/2), 1 without
    (a shallower crowning counts as none)."""
    cb = 0.0 if settings.crowning is None else settings.crowning
    return jnp.where(cb >= 0.5 * settings.accuracy.helix_slope, 0.5, 1.0)


def _face_factor(settings, cga, f_m_per_b):
    """K_Hβ (ISO 6336-1 clause 7): F_βx = B₂ f_Hβ (:func:`helix_modification_factor`: 0.5 with
    a crowning, else 1), at least 0.005 µm per N/mm of F_m/b (5e-12 m²/N); F_βy = F_βx − y_β
    (running-in); c_γβ = 0.85 c_γα; K_Hβ = 1 + F_βy c_γβ/(2 F_m/b) up to 2, else
    √(2 F_βy c_γβ/(F_m/b)) (F_m = F_t K_A K_v). Returns K_Hβ and its intermediate values
    (``F_betax_m``, ``F_betay_m``, ``c_gamma_beta_N_per_m2``, ``F_m_per_b_N_per_m``)."""
    acc, tr = settings.accuracy, settings.material.treatment
    b2 = helix_modification_factor(settings)
    f_bx = jnp.maximum(b2 * acc.helix_slope, 5e-12 * f_m_per_b)
    f_by = f_bx - tr.running_in_beta(f_bx, jnp.min(settings.material.sigma_h_lim))
    t = f_by * 0.85 * cga / f_m_per_b
    k = jnp.where(t <= 2.0, 1 + t / 2, jnp.sqrt(2 * jnp.maximum(t, 2.0)))
    return k, {"F_betax_m": f_bx, "F_betay_m": f_by, "c_gamma_beta_N_per_m2": 0.85 * cga,
               "F_m_per_b_N_per_m": f_m_per_b}


def _transverse_factors(geometry, g, settings, cga, f_th_per_b):
    """K_Hα and K_Fα (ISO 6336-1 clause 8, method B), limited to [1, ε_γ/(ε_α Z_ε²)] and [1, ε_γ/(0.25 ε_α +
    0.75)]."""
    acc, tr = settings.accuracy, settings.material.treatment
    ea, eb = g.transverse_contact_ratio, g.overlap_ratio
    eg = ea + eb
    f_eff = acc.base_pitch - tr.running_in_alpha(
        acc.base_pitch, jnp.min(settings.material.sigma_h_lim)
    )
    term = cga * f_eff / f_th_per_b
    k = jnp.where(
        eg <= 2,
        eg / 2 * (0.9 + 0.4 * term),
        0.9 + 0.4 * jnp.sqrt(2 * (eg - 1) / eg) * term,
    )
    z_eps = _contact_ratio_factor(ea, eb, geometry)
    kh = jnp.clip(k, 1.0, eg / (ea * z_eps**2))
    kf = jnp.clip(k, 1.0, eg / (0.25 * ea + 0.75))
    return kh, kf


def iso6336_load_factors(geometry, operating, settings) -> LoadFactors:
    """K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα at the operating point (module docstring; ISO 6336-1:2019
    clauses 6, 7, 8, method B); given factors replace computed ones. A given K_Hβ carries to
    K_Fβ (K_Fβ = K_Hβ^N_F, clause 7) and a given K_Hα to K_Fα (K_Fα = K_Hα, 8.3.4, within
    K_Fα's limits [1, ε_γ/(0.25 ε_α + 0.75)]) unless they are given too.

    The ISO 6336 editions' :meth:`~jaxgear.rating.AbstractRatingStandard.load_factors`; its
    arguments checked by the caller (:func:`jaxgear.rating.load_factors`)."""
    given = settings.given
    g = geometry.derived()
    ka = as_float(settings.application_factor)
    ft = _tangential_load(g, operating)
    line = ft * ka / g.face_width  # N/m
    c1, cga = _stiffness(geometry, g, settings, line)
    kv_iso, details = _dynamic_factor(geometry, g, operating, settings, (c1, cga), line)
    kv = kv_iso if given.K_v is None else as_float(given.K_v)
    khb_iso, face = _face_factor(settings, cga, line * kv)
    khb = khb_iso if given.K_Hbeta is None else as_float(given.K_Hbeta)
    h = (g.tip_diameter - g.root_diameter) / 2
    bh = jnp.maximum(jnp.min(geometry.face_width / h), 3.0)
    n_f = bh**2 / (1 + bh + bh**2)
    kfb = khb**n_f if given.K_Fbeta is None else as_float(given.K_Fbeta)
    kha, kfa = _transverse_factors(geometry, g, settings, cga, line * kv * khb)
    if given.K_Halpha is not None:
        kha = as_float(given.K_Halpha)
        # ISO 6336-1 8.3.4: K_Fα = K_Hα, within [1, ε_γ/(0.25 ε_α + 0.75)]
        ea, eg = g.transverse_contact_ratio, g.transverse_contact_ratio + g.overlap_ratio
        kfa = jnp.clip(kha, 1.0, eg / (0.25 * ea + 0.75))
    kfa = kfa if given.K_Falpha is None else as_float(given.K_Falpha)
    iso = "ISO 6336-1 method B"
    sources = {"K_A": "given"} | {
        k: ("given" if getattr(given, k) is not None else iso)
        for k in ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
    }
    details = details | face | {
        "c_prime_N_per_m2": c1,
        "c_gamma_alpha_N_per_m2": cga,
        "N_F": n_f,
        "B_2": helix_modification_factor(settings),
    }
    return LoadFactors(ka, kv, khb, kfb, kha, kfa, details, sources)


def face_load_factor(result) -> Array:
    """K_Hβ measured on a jaxgear load distribution: the largest load per unit face width over
    its mean, the load per unit face width of a slice being the sum of its cells' line loads
    over the contact lines (the slices have one face width b/N and one length on every line),
    averaged over the result's mesh positions (as ISO 6336-1's K_Hβ rests on the mean mesh
    stiffness c_γβ over a mesh cycle). Spur or helical; it includes whatever the result's model
    includes (lead modifications and deviations, body and shaft deflections of a scene).

    Args:
        result: a one-mesh result with ``line_load`` (N/m) and ``cell_mask`` of shape (P, L, N)
            (:class:`jaxgear.MeshResult`, a one-mesh :class:`jaxgear.QuasiStaticResult`), its
            positions uniform over whole mesh periods.

    Returns:
        K_Hβ (-), >= 1.
    """
    w = jnp.where(result.cell_mask, jnp.maximum(result.line_load, 0.0), 0.0)
    face = jnp.mean(jnp.sum(w, axis=-2), axis=0)  # (N,): mean over positions, summed lines
    # max/mean >= 1 but for round-off (a uniform load's mean one ulp above its max)
    return jnp.maximum(jnp.max(face) / jnp.mean(face), 1.0)


def transverse_load_factor(
    result, loaded: float = 1e-2, *, path_of_contact: float | None = None
) -> Array:
    """K_Hα measured on a jaxgear load distribution: the load sharing between the tooth pairs in
    contact. ISO 6336-1:2019 clause 8 defines K_Hα as accounting for the non-uniform
    distribution of the transverse load between the several pairs of teeth in contact at once;
    measured here, at each mesh position, as the largest mean line load of one contact line
    (one tooth pair: its load over its loaded length) over the mean line load of all the loaded
    cells (the total load over the total loaded length), the maximum over the positions. Equal
    sharing (a spur pair's two pairs carrying their load evenly, or one pair alone) gives 1;
    a pitch deviation or a modification that shifts load from one pair to the other gives
    more. A pair that has lost contact altogether (a pitch deviation larger than its
    deflection) is not in contact: its mate then carries the load alone, ratio 1 (ISO's cap
    ε_γ/(ε_α Z_ε²) covers that case); so this measures sharing, not lift-off.

    Contact beyond the theoretical path (``path_of_contact`` given): ISO's pairs in contact are
    those on the theoretical path [0, g_α], whose length ε_α counts (Z_ε, the limits of
    :func:`transverse_factor_limits`). A tip corner touching beyond it (premature engagement,
    late disengagement: docs/extended-contact.md) carries load that the pairs on the path then
    do not; it counts in the total load but not as a pair among which the load is shared: the
    numerator and the loaded length are read on the cells with 0 <= s <= g_α only (the mesh
    model's own test for the cells beyond the path). A corner thus relieves the pair it
    accompanies (ratio below 1, the result 1) rather than counting as a second pair that
    carries little (the corner of an unmodified pair taking 13 % of the load in the single
    contact zone would read 0.87/0.5 = 1.74 as a pair; it reads 1).

    Args:
        result: a one-mesh result with ``line_load`` (N/m) and ``cell_mask`` (P, L, N)
            (:class:`jaxgear.MeshResult`, a one-mesh :class:`jaxgear.QuasiStaticResult`), and
            ``cell_s`` (m) where ``path_of_contact`` is given.
        loaded: a cell is loaded above this fraction of the result's largest line load.
        path_of_contact: g_α (m) of the mesh (:attr:`jaxgear.MeshModel.path_of_contact`): a
            result of a mesh model with ``extended_contact`` needs it; None: every cell is on
            the path (a mesh model without contact beyond it).

    Returns:
        K_Hα (-), >= 1.

    Raises:
        ValueError: ``path_of_contact`` not > 0, or given for a result without ``cell_s``.
    """
    w = jnp.where(result.cell_mask, jnp.maximum(result.line_load, 0.0), 0.0)
    on = w > loaded * jnp.max(w)
    pair_load = w
    if path_of_contact is not None:
        check_real("path_of_contact", path_of_contact, "m", lo=0.0, lo_open=True, shape=(),
                   where="transverse_load_factor")
        if not hasattr(result, "cell_s"):
            raise ValueError(
                f"transverse_load_factor: result = {type(result).__name__} has no cell_s: "
                "allowed a result with cell_s where path_of_contact is given"
            )
        s = result.cell_s
        on_path = (s >= 0.0) & (s <= path_of_contact)
        on = on & on_path
        pair_load = jnp.where(on_path, w, 0.0)
    n_line = jnp.sum(on, axis=-1)  # (P, L) loaded cells per line on the path
    line_mean = jnp.sum(pair_load, axis=-1) / jnp.maximum(n_line, 1)
    all_mean = jnp.sum(w, axis=(-2, -1)) / jnp.maximum(jnp.sum(on, axis=(-2, -1)), 1)
    ratio = jnp.max(line_mean, axis=-1) / jnp.where(all_mean > 0, all_mean, 1.0)
    return jnp.maximum(jnp.max(ratio), 1.0)


def transverse_factor_limits(geometry) -> tuple[Array, Array]:
    """ISO 6336-1:2019 clause 8's upper limits of K_Hα and K_Fα: ε_γ/(ε_α Z_ε²) (the whole
    load on one pair at the critical point) and ε_γ/(0.25 ε_α + 0.75). A measured K_Hα
    (:func:`transverse_load_factor`) rates within them: beyond, the load sharing it measures
    (one pair carrying nearly all, e.g. a relieved pair that barely touches) is the single
    pair contact the rating's Z_ε, Z_B and Y_F already take. Returns (K_Hα max, K_Fα max)."""
    g = geometry.derived()
    ea, eb = g.transverse_contact_ratio, g.overlap_ratio
    eg = ea + eb
    z_eps = _contact_ratio_factor(ea, eb, geometry)
    return eg / (ea * z_eps**2), eg / (0.25 * ea + 0.75)


def _contact_ratio_factor(ea, eb, geometry):
    """Z_ε (contact ratio factor): spur √((4 − ε_α)/3); helical √((4 − ε_α)/3 (1 − ε_β) + ε_β/ε_α) for
    ε_β < 1, √(1/ε_α) from ε_β = 1."""
    eb1 = jnp.minimum(eb, 1.0)
    return jnp.sqrt((4 - ea) / 3 * (1 - eb1) + eb1 / ea)
