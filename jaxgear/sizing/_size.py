"""Every candidate of a sizing rated at once: its geometry (ISO 21771), its validity (the
checks :class:`jaxgear.GearPair` makes, and the spec's limits) and its ISO 6336 rating
(:func:`jaxgear.rating.rate`), one ``jax.jit(jax.vmap(...))`` program over chunks of
candidates (:func:`size`), into a table of every input and output with the reasons each
rejected candidate fails (:class:`SizingTable`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._geometry import involute
from ..rating import GearAccuracy, TracedTeethRatingGeometry, rate
from ..tribology import ts_scuffing
from ._candidates import Candidates, enumerate_candidates
from ._objectives import SCUFFING_COLUMNS, objective_columns
from ._scale import ChunkStore, rate_chunks, sizing_digest
from ._spec import SizingSpec

__all__ = ["CHECKS", "GEOMETRIC", "OUTPUTS", "SizingTable", "blank_mass", "candidate_outputs",
           "size"]

#: every check a candidate may fail, in the order the reasons are listed: name → what it asks
CHECKS = {
    "face_width": "the widest face allowed, min(b_max, (b/d1)_max d1), >= b_min",
    "outer_diameter": "each tip diameter <= the outer-diameter limit",
    "root": "each root diameter > 0",
    "tip": "each tip circle outside its base circle",
    "tip_thickness": "each normal tip thickness >= tip_thickness_min · m_n",
    "undercut": "each involute starts above the base circle (the rack's form circle roll >= 0)",
    "interference": "each active profile starts above its form circle",
    "tip_root_clearance": "each tip inside the mating root circle, a_w − r_a − r_f >= 0",
    "contact_ratio": "ε_α > 0 and ε_γ = ε_α + ε_β >= 1",
    "accuracy_scope": "ISO 1328-1's scope: 5 mm <= d <= 15000 mm, 4 mm <= b <= 1200 mm",
    "pitting": "S_H >= S_Hmin, both gears",
    "bending": "S_F >= S_Fmin, both gears",
    "scuffing": "S_B >= S_Bmin (ISO/TS 6336-20's closed form), with the spec's scuffing "
                "requirement (without it every candidate passes)",
}
#: the checks of the geometry itself: a candidate failing one has no rating (ISO's formulas
#: presume a valid pair); its rating columns are NaN
GEOMETRIC = ("root", "tip", "tip_thickness", "undercut", "interference", "tip_root_clearance",
             "contact_ratio", "accuracy_scope")

#: the table's per-candidate outputs of the batched program, in order
OUTPUTS = (
    "reference_diameter_1_m", "reference_diameter_2_m", "tip_diameter_1_m", "tip_diameter_2_m",
    "root_diameter_1_m", "root_diameter_2_m", "operating_pressure_angle_rad",
    "eps_alpha", "eps_beta", "eps_gamma", "tip_thickness_1_m", "tip_thickness_2_m",
    "form_roll_1_m", "form_roll_2_m", "mass_kg",
    "K_v", "K_Hbeta", "K_Halpha", "S_H1", "S_H2", "S_F1", "S_F2", *SCUFFING_COLUMNS,
)


def blank_mass(tip_diameter, root_diameter, face_width, density):
    """The mass (kg) of a gear blank of face width b: a solid cylinder of the root diameter
    with the teeth as half the annulus up to the tip (the teeth fill about half the ring
    between the root and tip circles), ρ b π (d_a² + d_f²)/8; no bore, web or hub."""
    return density * face_width * jnp.pi * (tip_diameter**2 + root_diameter**2) / 8


def _static(spec: SizingSpec) -> tuple:
    """The values of ``spec`` that shape the compiled program (angles, rack, grade, tip
    thickness limit)."""
    return (spec.normal_pressure_angle, spec.helix_angle, spec.addendum_coeff,
            spec.dedendum_coeff, spec.fillet_radius_coeff, spec.settings.accuracy.grade,
            spec.tip_thickness_min)


def candidate_outputs(spec: SizingSpec, normal_module, z1, z2, x1, x2, face_width,
                      helix_angle=None):
    """One candidate's outputs and checks, the function :func:`size` maps over the candidates
    (``jax.numpy``: traceable; called eagerly it rates one candidate).

    Args:
        spec: the :class:`SizingSpec` (its angles, rack, settings and operating point).
        normal_module: m_n (m). z1, z2: the tooth counts (floats, whole numbers). x1, x2: the
            profile shifts. face_width: b (m), both gears. helix_angle: β (rad, traceable: a
            refined design's), or None: the spec's.

    Returns:
        (outputs, passed): outputs (len(:data:`OUTPUTS`),) in that order (SI; the rating's
        entries meaningless where the geometry is invalid; the scuffing entries NaN without
        ``spec.scuffing``); passed, booleans of the checks
        of :data:`CHECKS` but ``face_width`` and ``outer_diameter`` (the space limits
        :func:`size` reads off the table), in that order, True where passed.
    """
    c = {"m": normal_module, "z1": z1, "z2": z2, "x1": x1, "x2": x2, "b": face_width}
    static = _static(spec)
    if helix_angle is not None:
        static = (static[0], helix_angle) + static[2:]
    return _one(c, static, spec.settings, spec.operating, scuffing=spec.scuffing)


def _one(c, spec_static, settings, operating, margins=False, scuffing=None):
    """The outputs (:data:`OUTPUTS`) and the checks (:data:`CHECKS`, True = passed) of one
    candidate ``c`` (a dict of scalars: m, z1, z2, x1, x2, b), rated for scuffing with
    ``scuffing`` (a :class:`jaxgear.sizing.ScuffingRequirement`, or None: NaN, passed); with
    ``margins`` also the geometric checks' continuous margins (m, each >= 0 where passed: the
    refinement's constraints) and the centre distance (m)."""
    an, beta, ha, hf, rho, grade, s_min_t = spec_static
    m, z = c["m"], jnp.stack([c["z1"], c["z2"]])
    x = jnp.stack([c["x1"], c["x2"]])
    b = c["b"]
    two = jnp.ones(2)
    geometry = TracedTeethRatingGeometry(
        teeth=z, normal_module=m, normal_pressure_angle=jnp.asarray(an), helix_angle=jnp.asarray(beta),
        profile_shift=x, addendum_coeff=ha * two, dedendum_coeff=hf * two,
        fillet_radius_coeff=rho * two, face_width=b * two, rim_thickness=(None, None),
        center_distance=None,
    )
    g = geometry.derived()
    d, db, da, df = g.reference_diameter, g.base_diameter, g.tip_diameter, g.root_diameter
    at, awt, a = g.transverse_pressure_angle, g.operating_pressure_angle, g.center_distance
    mt = g.transverse_module
    # tip thickness (transverse, ISO 21771), carried to the normal section at the tip helix
    st = mt * (jnp.pi / 2 + 2 * x * jnp.tan(an))
    aa = jnp.arccos(jnp.clip(db / da, -1.0, 1.0))
    s_at = da * (st / d + involute(at) - involute(aa))
    beta_a = jnp.arctan(jnp.tan(beta) * da / d)
    s_an = s_at * jnp.cos(beta_a)
    # the rack's form circle (undercut), the start of active profile (interference)
    h = m * (hf - x - rho * (1 - jnp.sin(an)))
    form = d / 2 * jnp.sin(at) - h / jnp.sin(at)
    line = a * jnp.sin(awt)
    roll_tip = jnp.sqrt(jnp.maximum(da**2 - db**2, 0.0)) / 2
    start = jnp.stack([line - roll_tip[1], line - roll_tip[0]])
    clear = jnp.stack([a - da[0] / 2 - df[1] / 2, a - da[1] / 2 - df[0] / 2])
    ea, eb = g.transverse_contact_ratio, g.overlap_ratio
    mass = jnp.sum(blank_mass(da, df, b, settings.material.density))
    accuracy = GearAccuracy.from_dimensions(m, d, b * two, grade)
    r = rate(geometry, operating, eqx.tree_at(lambda s: s.accuracy, settings, accuracy))
    s_h, s_f = r.pitting.S_H, r.bending.S_F
    f = r.factors
    if scuffing is None:
        sc, s_b_ok = [jnp.full((), jnp.nan, dtype=s_h.dtype)] * len(SCUFFING_COLUMNS), True
    else:
        t = ts_scuffing(c["z1"], c["z2"] / c["z1"], a, awt, g.base_helix_angle, d[0], da, b,
                        (ea, eb), operating.torque, operating.speed,
                        f.K_A * f.K_v * f.K_Hbeta * f.K_Halpha, scuffing.lubricant,
                        scuffing.roughness, scuffing.limits, settings.material.youngs_modulus,
                        settings.material.poisson_ratio, bulk=scuffing.bulk, grade=grade)
        sc = [t.safety_factor, t.max_contact_temperature, t.max_flash_temperature,
              t.bulk_temperature, t.friction_coefficient, t.integral_safety_factor]
        s_b_ok = t.safety_factor >= scuffing.min_safety
    outputs = jnp.stack([
        d[0], d[1], da[0], da[1], df[0], df[1], awt, ea, eb, ea + eb, s_an[0], s_an[1],
        form[0], form[1], mass, f.K_v, f.K_Hbeta, f.K_Halpha,
        s_h[0], s_h[1], s_f[0], s_f[1], *(jnp.asarray(v, s_h.dtype) for v in sc),
    ])
    checks = {
        "root": jnp.all(df > 0),
        "tip": jnp.all(da > db),
        "tip_thickness": jnp.all(s_an >= s_min_t * m),
        "undercut": jnp.all(form >= 0),
        "interference": jnp.all(start >= form - 1e-12),
        "tip_root_clearance": jnp.all(clear >= -1e-12),
        "contact_ratio": (ea > 0) & (ea + eb >= 1.0),
        "accuracy_scope": (jnp.all(d >= 5e-3) & jnp.all(d <= 15.0) & (b >= 4e-3) & (b <= 1.2)),
        "pitting": jnp.all(s_h >= settings.min_safety_pitting),
        "bending": jnp.all(s_f >= settings.min_safety_bending),
        "scuffing": jnp.asarray(s_b_ok),
    }
    passed = jnp.stack([checks[k] for k in CHECKS if k in checks])
    if margins:
        return outputs, passed, {"root": df, "tip": da - db, "tip_thickness": s_an - s_min_t * m,
                                 "undercut": form, "interference": start - form,
                                 "tip_root_clearance": clear, "centre_distance": a}
    return outputs, passed


@dataclasses.dataclass(frozen=True)
class SizingTable:
    """Every candidate of a sizing with its inputs, outputs and the checks it fails.

    Attributes:
        columns: name → array of shape (n,), SI units in the names: the inputs
            ``normal_module_m``, ``z1``, ``z2``, ``ratio``, ``ratio_error``, ``x1``, ``x2``,
            ``face_width_m``, ``centre_distance_m``; the outputs :data:`OUTPUTS` (diameters,
            the operating pressure angle, ε_α, ε_β, ε_γ, normal tip thicknesses, the rack's form
            circle roll, the blanks' mass (:func:`blank_mass`), K_v, K_Hβ, K_Hα, S_H and S_F per
            gear: NaN where the geometry is invalid, :data:`GEOMETRIC`); with the spec's
            ``scuffing`` the scuffing rating's :data:`jaxgear.sizing.SCUFFING_COLUMNS` (S_B,
            θ_B,max, θ_fl,max, θ_M, μ_mC, S_intS; NaN likewise); ``least_margin`` the least of
            S_H/S_Hmin, S_F/S_Fmin and (with ``scuffing``) S_B/S_Bmin (NaN likewise); ``volume_m3`` the envelope's
            and, with the spec's ``mesh_loss``, the mesh loss's ``friction_coefficient``,
            ``loss_factor``, ``mesh_loss_W``, ``efficiency`` (NaN likewise;
            :func:`jaxgear.sizing.objective_columns`).
        failed: (n, len(CHECKS)) booleans, True where the candidate fails the check
            (:data:`CHECKS`, in that order).
    """

    columns: dict
    failed: np.ndarray

    def __len__(self) -> int:
        return int(self.failed.shape[0])

    @property
    def feasible(self) -> np.ndarray:
        """(n,) True where the candidate fails no check."""
        return ~self.failed.any(axis=1)

    def reasons(self) -> list[str]:
        """Each candidate's failed checks, joined by ``;`` in :data:`CHECKS`' order ("" where
        feasible)."""
        names = list(CHECKS)
        return [";".join(names[j] for j in np.flatnonzero(row)) for row in self.failed]

    def ranked(self) -> np.ndarray:
        """The indices of the feasible candidates, lightest first, then the largest least
        margin (``least_margin``) first."""
        idx = np.flatnonzero(self.feasible)
        mass, margin = self.columns["mass_kg"][idx], self.columns["least_margin"][idx]
        return idx[np.lexsort((-margin, mass))]


def size(spec: SizingSpec, *, chunk: int = 2048,
         progress: Callable[[int, int], None] | None = None, devices=None,
         store=None, restart: bool = False) -> SizingTable:
    """Rate every candidate of ``spec`` (:func:`jaxgear.sizing.enumerate_candidates`): geometry,
    validity and ISO 6336 (the settings' standard, :func:`jaxgear.rating.rate` of a
    :class:`jaxgear.rating.TracedTeethRatingGeometry`, each candidate with the ISO 1328-1
    tolerances of its own dimensions) in one compiled ``vmap`` program per chunk size, the
    chunks sharded over the devices (one chunk per device at a time) and, under
    ``jax.distributed``, over every process's devices (every process calling this with the
    same arguments, every process receiving the whole table). A candidate's numbers are the
    same bits whatever the devices, the processes, or a resumed store.

    Args:
        spec: the :class:`SizingSpec`.
        chunk: candidates per call of the compiled program on one device (its memory grows
            with it); every call takes a whole chunk (one compiled shape): the last is padded
            with copies of the last candidate and the copies dropped.
        progress: called as ``progress(done, total)`` after each chunk (and once with the
            candidates a resumed store held), or None.
        devices: the devices to shard the chunks over (default: ``jax.devices()``, every
            global device).
        store: a folder for the results store (one file per finished chunk, written by process
            0; a rerun of the same sizing into it rates only the chunks missing), or None.
        restart: a store holding another sizing's chunks (another spec, chunk or jaxgear
            version) emptied instead of refused.

    Returns:
        :class:`SizingTable` of every candidate (possibly none: an empty table).

    Raises:
        ValueError: ``chunk`` not a positive integer; ``store`` holding another sizing's
            chunks (without ``restart``); one line each, before any candidate is rated.
    """
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise ValueError(f"size: chunk = {chunk!r} is out of range: allowed an integer >= 1")
    cands = enumerate_candidates(spec)
    n = len(cands)
    static = _static(spec)
    fields = {"m": cands.normal_module, "z1": cands.z1.astype(float),
              "z2": cands.z2.astype(float), "x1": cands.x1, "x2": cands.x2,
              "b": cands.face_width}
    n_checks = sum(1 for k in CHECKS if k not in ("face_width", "outer_diameter"))
    # numbers as arrays: specs that differ in them share the compiled program
    args = program_arguments(spec)
    widths = (len(OUTPUTS), n_checks)
    if store is not None:
        names = (OUTPUTS, tuple(CHECKS))
        digest = sizing_digest(chunk, names, static, args, fields)
        store = ChunkStore(store, digest, n, chunk)
    outs, checks = rate_chunks(_local, static, args, fields, n, chunk, widths,
                               devices=devices, store=store, restart=restart,
                               progress=progress)
    return _table(spec, cands, outs, checks)


def program_arguments(spec: SizingSpec) -> tuple:
    """(settings, operating point, scuffing requirement) of ``spec``, their numbers as arrays:
    the compiled programs' arguments (specs that differ in them share the program)."""
    return jax.tree_util.tree_map(
        lambda v: jnp.asarray(v, dtype=float) if isinstance(v, float) else v,
        (spec.settings, spec.operating, spec.scuffing))


def _local(static, settings, operating, scuffing, batch):
    """:func:`_one` mapped over a chunk of candidates (one device's share: the program
    :func:`jaxgear.sizing._scale.rate_chunks` compiles once per chunk size and per spec's
    static values: angles, rack, grade, tip thickness; the settings' and operating point's
    numbers are arguments, so specs that differ in them share it)."""
    return jax.vmap(lambda c: _one(c, static, settings, operating, scuffing=scuffing))(batch)


def _table(spec: SizingSpec, cands: Candidates, outs, checks, helix_angle=None) -> SizingTable:
    """The table of ``cands`` from the program's outputs and checks: the inputs, the outputs,
    the space limits' checks and the objectives' columns. ``helix_angle``: each candidate's β
    (rad, shape (n,)), or None: the spec's for all (a refined design's own otherwise)."""
    col = dict(zip(OUTPUTS, outs.T, strict=True))
    b_min = spec.face_width[0]
    limit = np.inf if spec.outer_diameter_max is None else spec.outer_diameter_max
    space = np.stack([
        cands.face_width < b_min * (1 - 1e-12),
        np.maximum(col["tip_diameter_1_m"], col["tip_diameter_2_m"]) > limit,
    ], axis=1)
    failed = np.concatenate([space, ~checks], axis=1) if len(cands) else np.zeros((0, len(CHECKS)), bool)
    geometric = failed[:, [list(CHECKS).index(k) for k in GEOMETRIC]].any(axis=1)
    for k in OUTPUTS[OUTPUTS.index("K_v"):]:
        col[k] = np.where(geometric, np.nan, col[k])
    margin = np.minimum(
        np.minimum(col["S_H1"], col["S_H2"]) / float(spec.settings.min_safety_pitting),
        np.minimum(col["S_F1"], col["S_F2"]) / float(spec.settings.min_safety_bending),
    )
    if spec.scuffing is None:  # no scuffing rating: no columns
        for k in SCUFFING_COLUMNS:
            del col[k]
    else:
        margin = np.minimum(margin, col["S_B"] / float(spec.scuffing.min_safety))
    ratio = cands.z2 / np.maximum(cands.z1, 1)
    columns = {
        "normal_module_m": cands.normal_module, "z1": cands.z1, "z2": cands.z2, "ratio": ratio,
        "ratio_error": ratio / spec.ratio - 1, "x1": cands.x1, "x2": cands.x2,
        "face_width_m": cands.face_width, "centre_distance_m": cands.centre_distance,
        "helix_angle_rad": (np.full(len(cands), float(spec.helix_angle)) if helix_angle is None
                            else np.asarray(helix_angle, dtype=float)),
        **col, "least_margin": margin,
    }
    columns |= objective_columns(spec, columns, geometric)  # volume, mesh loss
    return SizingTable(columns, failed)
