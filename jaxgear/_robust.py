"""Robust design at scale: Monte Carlo over ISO 1328-1 deviation realisations, vmapped, sharded
over the global device mesh and, across processes, run with ``jax.distributed``
(docs/robust.md, the Monte Carlo over deviation realisations).

* :class:`DeviationSampler` draws a :class:`~jaxgear.Deviations` (both gears, every tooth) of an
  ISO 1328-1 flank tolerance class from a ``jax.random`` key: the distributions of
  :func:`~jaxgear.sample_gear_deviations` (docs/deviations.md, "Random draws"), in JAX, so that a
  realisation is a pure function of its key (vmapped, sharded, differentiated through).
* :func:`sample_metrics` evaluates one realisation: the quasi-static TE RMS, peak-to-peak TE and
  the largest line load over a span of pinion angles (whole revolutions);
  :class:`QuasiStaticMetrics` holds that problem as a module.
* :func:`robust_samples` evaluates realisations 0 … N−1 (realisation i draws from
  ``jax.random.fold_in(key, i)``, whatever the number of devices or processes), sharded over a
  1-D mesh of every global device (``jax.shard_map``), in batches of ``batch_size`` per device
  (``jax.lax.map``), gathered on every process
  (:func:`jaxgear._sharding.gathered`).
* :func:`sample_statistics` (NumPy): mean, standard deviation and percentiles with confidence
  intervals (the mean's from the normal approximation, the percentiles' distribution-free from
  the order statistics and the binomial distribution).
"""

from __future__ import annotations

import abc
import math
from statistics import NormalDist
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec as P
from jaxtyping import Array, Float, Int

from ._baseplane import MeshModel
from ._contact import ContactLaw, ExactContact
from ._deviations import Deviations, GearDeviations, iso1328_tolerances
from ._modifications import Modifications
from ._quasi_static import quasi_static
from ._sharding import gathered
from ._util import NamedKind, compiled_when_eager
from .scenes import Scene

__all__ = [
    "DEVIATION_KINDS",
    "AbstractDeviationKind",
    "DeviationSampler",
    "GearSampler",
    "HelixDeviation",
    "PitchDeviation",
    "ProfileDeviation",
    "QuasiStaticMetrics",
    "RobustMetrics",
    "RunoutDeviation",
    "binomial_quantile",
    "robust_samples",
    "sample_mesh",
    "sample_metrics",
    "sample_statistics",
]

#: points of the trace over which the total profile (helix) deviation is measured (as
#: :func:`jaxgear._deviations.total_range`)
_TRACE_POINTS = 201


def _slope_form(key, z, slope_tol, form_tol, total_tol):
    """Per tooth slope ~ U(−slope_tol, slope_tol), form ~ U(−form_tol, form_tol), both scaled
    down together where the trace's range over x ∈ [0, 1] exceeds total_tol."""
    ks, kf = jax.random.split(key)
    dtype = slope_tol.dtype
    slope = jax.random.uniform(ks, (z,), dtype, -1.0, 1.0) * slope_tol
    form = jax.random.uniform(kf, (z,), dtype, -1.0, 1.0) * form_tol
    x = jnp.linspace(0.0, 1.0, _TRACE_POINTS, dtype=dtype)[:, None]
    trace = slope[None, :] * (x - 0.5) + form[None, :] * (2.0 * x - 1.0) ** 2
    total = jnp.max(trace, axis=0) - jnp.min(trace, axis=0)
    s = jnp.minimum(1.0, total_tol / jnp.maximum(total, jnp.finfo(dtype).tiny))
    return slope * s, form * s


class AbstractDeviationKind(NamedKind):
    """A kind of ISO 1328-1 deviation a :class:`GearSampler` draws (docs/deviations.md,
    "Random draws"): :meth:`draw` gives the :class:`~jaxgear.GearDeviations` fields it sets. A
    new kind is one subclass (and its case-file name in :mod:`jaxgear.io`)."""

    @abc.abstractmethod
    def draw(self, keys, teeth: int, tolerances: Float[Array, " 9"]) -> dict[str, Array]:
        """The fields this kind draws.

        Args:
            keys: the sampler's five ``jax.random`` keys (pitch, runout, runout phase, profile,
                helix), each kind drawing from its own.
            teeth: z. tolerances: the sampler's (9,) tolerances (m), :class:`GearSampler`'s order.

        Returns:
            ``{field name: value}`` of :class:`~jaxgear.GearDeviations` (m, rad), per tooth (z,)
            or scalars.
        """


class PitchDeviation(AbstractDeviationKind):
    """Single pitch u_n ~ U(−f_pT, f_pT), closed (u_n − ū), scaled by
    s = min(1, f_pT/max|f_pt|, F_pT/(max F_p − min F_p)) (case-file name "pitch")."""

    name: ClassVar[str] = "pitch"

    def draw(self, keys, teeth, tolerances):
        t = tolerances
        u = jax.random.uniform(keys[0], (teeth,), t.dtype, -1.0, 1.0) * t[0]
        u = u - jnp.mean(u)
        cum = jnp.cumsum(u) - u[0]
        tiny = jnp.finfo(t.dtype).tiny
        scale = jnp.minimum(
            1.0,
            jnp.minimum(
                t[0] / jnp.maximum(jnp.max(jnp.abs(u)), tiny),
                t[1] / jnp.maximum(jnp.max(cum) - jnp.min(cum), tiny),
            ),
        )
        return {"single_pitch": u * scale}


class RunoutDeviation(AbstractDeviationKind):
    """Runout F_r ~ U(0, F_rT), phase φ ~ U(0, 2π) (case-file name "runout")."""

    name: ClassVar[str] = "runout"

    def draw(self, keys, teeth, tolerances):
        dtype = tolerances.dtype
        return {
            "runout": jax.random.uniform(keys[1], (), dtype) * tolerances[8],
            "runout_phase": jax.random.uniform(keys[2], (), dtype) * (2.0 * jnp.pi),
        }


class ProfileDeviation(AbstractDeviationKind):
    """Per tooth profile slope ~ U(−f_HαT, f_HαT) and form ~ U(−f_fαT, f_fαT), scaled down
    together where the trace's range exceeds F_αT (case-file name "profile")."""

    name: ClassVar[str] = "profile"

    def draw(self, keys, teeth, tolerances):
        t = tolerances
        slope, form = _slope_form(keys[3], teeth, t[2], t[3], t[4])
        return {"profile_slope": slope, "profile_form": form}


class HelixDeviation(AbstractDeviationKind):
    """Per tooth helix slope ~ U(−f_HβT, f_HβT) and form ~ U(−f_fβT, f_fβT), scaled down
    together where the trace's range exceeds F_βT (case-file name "helix")."""

    name: ClassVar[str] = "helix"

    def draw(self, keys, teeth, tolerances):
        t = tolerances
        slope, form = _slope_form(keys[4], teeth, t[5], t[6], t[7])
        return {"helix_slope": slope, "helix_form": form}


#: the deviations a sampler can draw, all by default (docs/deviations.md, "Deviation model")
DEVIATION_KINDS = (PitchDeviation(), RunoutDeviation(), ProfileDeviation(), HelixDeviation())


def _check_kinds(kinds) -> tuple[AbstractDeviationKind, ...]:
    kinds = tuple(kinds)
    ok = all(isinstance(k, AbstractDeviationKind) for k in kinds)
    if not ok or not kinds or len({type(k) for k in kinds}) != len(kinds):
        raise ValueError(
            f"kinds = {kinds!r} is out of range: allowed distinct kinds among "
            "jaxgear.PitchDeviation(), jaxgear.RunoutDeviation(), jaxgear.ProfileDeviation(), "
            "jaxgear.HelixDeviation()"
        )
    return kinds


class GearSampler(eqx.Module):
    """Draws one gear's deviations (:class:`~jaxgear.GearDeviations`) of an ISO 1328-1 flank
    tolerance class from a ``jax.random`` key.

    Distributions (docs/deviations.md, "Random draws"; as :func:`~jaxgear.sample_gear_deviations`,
    all independent): single pitch u_n ~ U(−f_pT, f_pT), closed (u_n − ū), scaled by
    s = min(1, f_pT/max|f_pt|, F_pT/(max F_p − min F_p)); runout F_r ~ U(0, F_rT), phase
    φ ~ U(0, 2π); per tooth profile slope ~ U(−f_HαT, f_HαT) and form ~ U(−f_fαT, f_fαT), scaled
    down together where the trace's range exceeds F_αT; the helix likewise (f_HβT, f_fβT, F_βT).
    The kinds not in ``kinds`` are 0 (each kind, an :class:`AbstractDeviationKind`, draws its
    own fields from its own key).

    Attributes:
        tolerances: (f_pT, F_pT, f_HαT, f_fαT, F_αT, f_HβT, f_fβT, F_βT, F_rT) (m), shape (9,)
            (:class:`~jaxgear.ISO1328Tolerances` in that order).
        reference_pressure_angle: α_t (rad) of the reference circle of the pitch deviations.
        teeth: z (static). kinds: the deviations drawn, a tuple of distinct
            :class:`AbstractDeviationKind` (:data:`DEVIATION_KINDS`: all four; static).
    """

    tolerances: Float[Array, " 9"]
    reference_pressure_angle: Float[Array, ""]
    teeth: int = eqx.field(static=True)
    kinds: tuple[AbstractDeviationKind, ...] = eqx.field(
        static=True, default=DEVIATION_KINDS
    )

    def __check_init__(self):
        if isinstance(self.teeth, bool) or int(self.teeth) != self.teeth or self.teeth < 2:
            raise ValueError(f"teeth = {self.teeth!r} is out of range: allowed an integer >= 2")
        _check_kinds(self.kinds)
        if self.tolerances.shape != (9,):
            raise ValueError(
                f"tolerances: shape {self.tolerances.shape} is out of range: allowed (9,) "
                "(f_pT, F_pT, f_HaT, f_faT, F_aT, f_HbT, f_fbT, F_bT, F_rT)"
            )

    @classmethod
    def of(cls, tolerances, teeth: int, reference_pressure_angle=0.0, kinds=DEVIATION_KINDS):
        """A sampler from :class:`~jaxgear.ISO1328Tolerances` (m)."""
        t = tolerances
        values = (
            t.single_pitch,
            t.cumulative_pitch,
            t.profile_slope,
            t.profile_form,
            t.profile_total,
            t.helix_slope,
            t.helix_form,
            t.helix_total,
            t.runout,
        )
        dtype = jnp.result_type(float)
        return cls(
            jnp.asarray(values, dtype),
            jnp.asarray(reference_pressure_angle, dtype),
            int(teeth),
            _check_kinds(kinds),
        )

    @compiled_when_eager
    def __call__(self, key) -> GearDeviations:
        """One gear's deviations drawn from ``key`` (a ``jax.random`` key)."""
        z, t = self.teeth, self.tolerances
        keys = jax.random.split(key, 5)
        zeros = jnp.zeros((z,), t.dtype)
        scalar = jnp.zeros((), t.dtype)
        fields = {
            "single_pitch": zeros,
            "runout": scalar,
            "runout_phase": scalar,
            "profile_slope": zeros,
            "profile_form": zeros,
            "helix_slope": zeros,
            "helix_form": zeros,
        }
        for kind in self.kinds:
            fields.update(kind.draw(keys, z, t))
        return GearDeviations(**fields, reference_pressure_angle=self.reference_pressure_angle)


class DeviationSampler(eqx.Module):
    """Draws the deviations of a gear pair (:class:`~jaxgear.Deviations`) from a ``jax.random``
    key: a pure function of the key, so realisations vmap, shard and differentiate.

    Build it for an accuracy grade with :meth:`for_grade`. The pinion draws from the first and
    the gear from the second half of ``jax.random.split(key)``.

    Attributes:
        pinion, gear: a :class:`GearSampler` each, or None (a perfect member).
    """

    pinion: GearSampler | None = None
    gear: GearSampler | None = None

    @classmethod
    def for_grade(
        cls,
        pair,
        grade: int,
        *,
        members: tuple[str, ...] = ("pinion", "gear"),
        kinds: tuple[AbstractDeviationKind, ...] = DEVIATION_KINDS,
    ) -> DeviationSampler:
        """The sampler of ISO 1328-1:2013 flank tolerance class ``grade`` for ``pair`` (a
        :class:`~jaxgear.GearPair`): each gear's tolerances from its own reference diameter
        d = z m_n / cos β and face width (:func:`~jaxgear.iso1328_tolerances`).

        Args:
            pair: the :class:`~jaxgear.GearPair`. grade: the class, an integer 1 to 11.
            members: the gears that deviate ("pinion", "gear"; the others are perfect).
            kinds: the deviations drawn, distinct :class:`AbstractDeviationKind` objects
                (default :data:`DEVIATION_KINDS`, all four).

        Raises:
            ValueError: a grade, a size or a helix angle outside ISO 1328-1's scope, unknown
                members or kinds (one line naming the value and the allowed range).
        """
        members = tuple(members)
        if not members or any(m not in ("pinion", "gear") for m in members):
            raise ValueError(
                f"members = {members!r} is out of range: allowed names among ('pinion', 'gear')"
            )
        kinds = _check_kinds(kinds)
        out = {}
        for tag in ("pinion", "gear"):
            if tag not in members:
                out[tag] = None
                continue
            member = getattr(pair, tag)
            d = member.teeth * pair.normal_module / math.cos(pair.helix_angle)
            tol = iso1328_tolerances(pair.normal_module, d, member.face_width, grade)
            out[tag] = GearSampler.of(tol, member.teeth, pair.transverse_pressure_angle, kinds)
        return cls(**out)

    @compiled_when_eager
    def __call__(self, key) -> Deviations:
        """A realisation drawn from ``key``."""
        kp, kg = jax.random.split(key)
        return Deviations(
            pinion=None if self.pinion is None else self.pinion(kp),
            gear=None if self.gear is None else self.gear(kg),
        )


class RobustMetrics(eqx.Module):
    """What one realisation gives (each a scalar; with a leading sample axis (N,) from
    :func:`robust_samples`).

    Attributes:
        te_rms: RMS of the quasi-static TE about its mean over the span (m).
        te_ptp: peak-to-peak TE over the span (m).
        max_line_load: largest load per unit contact length over the span (N/m).
        result: the worst :class:`~jaxgear.ContactResult` code over the span (0: every position
            converged).
    """

    te_rms: Float[Array, "*N"]
    te_ptp: Float[Array, "*N"]
    max_line_load: Float[Array, "*N"]
    result: Int[Array, "*N"]


def sample_metrics(
    scene: Scene | MeshModel,
    modifications: Modifications | None,
    deviations: Deviations,
    torque,
    theta: Float[Array, " P"],
    *,
    contact: ContactLaw = ExactContact(),
) -> RobustMetrics:
    """The quasi-static metrics of one deviation realisation over the pinion angles ``theta``.

    Args:
        scene: a :class:`~jaxgear.scenes.Scene` of one mesh or a :class:`~jaxgear.MeshModel`.
        modifications: the flank modifications (None: perfect involutes); their own
            ``deviations`` are replaced by ``deviations``.
        deviations: the realisation (:class:`~jaxgear.Deviations`, e.g. from a
            :class:`DeviationSampler`).
        torque: pinion torque (N·m), > 0.
        theta: pinion angles (rad), shape (P,): whole revolutions for a result that does not
            depend on the start (``mesh_positions(mesh, n, z1 * revolutions)``).
        contact: the contact law (exact by default; :class:`~jaxgear.SmoothContact` for
            gradients through the realisations).

    Returns:
        :class:`RobustMetrics`. Failed positions are reported in ``result``, never raised (the
        realisations run vmapped).
    """
    mods = Modifications() if modifications is None else modifications
    mods = Modifications(mods.pinion, mods.gear, deviations=deviations)
    res = quasi_static(scene, mods, torque, theta, contact=contact, throw=False)
    te = res.transmission_error
    return RobustMetrics(
        te_rms=jnp.sqrt(jnp.mean((te - jnp.mean(te)) ** 2)),
        te_ptp=jnp.max(te) - jnp.min(te),
        max_line_load=jnp.max(res.line_load),
        result=jnp.max(res.result),
    )


class QuasiStaticMetrics(eqx.Module):
    """The quasi-static problem a realisation is evaluated on (:func:`sample_metrics` as a
    module, for :func:`robust_samples`): called with a :class:`~jaxgear.Deviations`, returns a
    :class:`RobustMetrics`.

    Attributes:
        scene: scene of one mesh or :class:`~jaxgear.MeshModel`. modifications: flank
            modifications (None: perfect). torque: pinion torque (N·m). theta: pinion angles
            (rad), (P,). contact: the contact law.
    """

    scene: Scene | MeshModel
    modifications: Modifications | None
    torque: Float[Array, ""]
    theta: Float[Array, " P"]
    contact: ContactLaw = ExactContact()

    def __call__(self, deviations: Deviations) -> RobustMetrics:
        return sample_metrics(
            self.scene,
            self.modifications,
            deviations,
            self.torque,
            self.theta,
            contact=self.contact,
        )


def sample_mesh(devices=None) -> Mesh:
    """A 1-D mesh (axis ``"samples"``) of ``devices`` (default: every global device, of every
    process under ``jax.distributed``)."""
    devices = jax.devices() if devices is None else list(devices)
    return Mesh(np.asarray(devices), ("samples",))


@eqx.filter_jit
def _sharded(problem, sampler, key, index, mesh, batch_size):
    dyn, static = eqx.partition((problem, sampler, key), eqx.is_array)

    def local(dyn, index):
        problem, sampler, key = eqx.combine(dyn, static)

        def one(i):
            return problem(sampler(jax.random.fold_in(key, i)))

        return jax.lax.map(one, index, batch_size=batch_size)

    return jax.shard_map(
        local,
        mesh=mesh,
        in_specs=(P(), P("samples")),
        out_specs=P("samples"),
        check_vma=False,  # the contact loops start from replicated carries
    )(dyn, index)


def _replicated(tree, mesh: Mesh):
    """Every array leaf of ``tree`` as a global array replicated over ``mesh`` (the same value
    on every process: each process passes its own copy)."""
    sharding = NamedSharding(mesh, P())

    def put(x):
        if not eqx.is_array(x):
            return x
        if jnp.issubdtype(x.dtype, jax.dtypes.prng_key):
            data = np.asarray(jax.random.key_data(x))
            impl = jax.random.key_impl(x)
            g = jax.make_array_from_callback(data.shape, sharding, lambda idx: data[idx])
            return jax.random.wrap_key_data(g, impl=impl)
        host = np.asarray(x)
        return jax.make_array_from_callback(host.shape, sharding, lambda idx: host[idx])

    return jax.tree.map(put, tree)


def robust_samples(
    problem,
    sampler: DeviationSampler,
    key,
    samples: int,
    *,
    batch_size: int = 16,
    devices=None,
):
    """Evaluate ``problem`` on ``samples`` deviation realisations, sharded over devices.

    Realisation i is ``problem(sampler(jax.random.fold_in(key, i)))``, the same whatever the
    number of devices or processes. The indices are padded to a multiple of the device count and
    sharded over a 1-D mesh of every global device (``jax.shard_map``); each device maps over
    its share in vmapped batches of ``batch_size`` (``jax.lax.map``, memory ∝ batch_size). Under
    ``jax.distributed`` (one process per host, every process calling this with the same
    arguments) the devices of every process take part and every process receives every
    realisation (``process_allgather``).

    Args:
        problem: a module (e.g. :class:`QuasiStaticMetrics`) mapping a
            :class:`~jaxgear.Deviations` to a pytree of arrays (per realisation).
        sampler: a :class:`DeviationSampler`.
        key: a ``jax.random`` key (``jax.random.key(seed)``).
        samples: N, an integer >= 1.
        batch_size: realisations vmapped together on a device, an integer >= 1.
        devices: the devices to shard over (default: ``jax.devices()``, every global device).

    Returns:
        ``problem``'s output pytree with a leading axis (N,), as NumPy arrays on every process.

    Raises:
        ValueError: samples or batch_size not an integer >= 1, a sampler that is not a
            :class:`DeviationSampler`.
    """
    for name, v in (("samples", samples), ("batch_size", batch_size)):
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
            raise ValueError(f"{name} = {v!r} is out of range: allowed an integer >= 1")
    if not isinstance(sampler, DeviationSampler):
        raise ValueError(f"sampler = {type(sampler).__name__}: allowed a DeviationSampler")
    mesh = sample_mesh(devices)
    n_dev = mesh.devices.size
    per_device = -(-int(samples) // n_dev)
    total = per_device * n_dev
    index = np.arange(total, dtype=np.int32)
    sharding = NamedSharding(mesh, P("samples"))
    index = jax.make_array_from_callback(index.shape, sharding, lambda idx: index[idx])
    problem, sampler, key = _replicated((problem, sampler, key), mesh)
    out = _sharded(problem, sampler, key, index, mesh, min(int(batch_size), per_device))
    return jax.tree.map(lambda a: a[: int(samples)], gathered(out))


# --------------------------------------------------------------------------------------------
# statistics (NumPy)


def binomial_quantile(level: float, n: int, p: float) -> int:
    """The smallest k with P(B <= k) >= ``level``, B ~ Binomial(n, p) (the quantile function
    of the binomial distribution, as ``scipy.stats.binom.ppf``), from the log-pmf by
    ``math.lgamma`` (exact to round-off; cost ∝ n)."""
    k = np.arange(n + 1)
    lg = np.vectorize(math.lgamma)
    logpmf = (
        lg(n + 1.0) - lg(k + 1.0) - lg(n - k + 1.0) + k * math.log(p) + (n - k) * math.log1p(-p)
    )
    cdf = np.cumsum(np.exp(logpmf))
    return int(min(np.searchsorted(cdf, level * (1.0 - 1e-12)), n))


def sample_statistics(
    values,
    percentiles=(5.0, 50.0, 95.0),
    confidence: float = 0.95,
) -> dict:
    """Mean, standard deviation and percentiles of a sample, with confidence intervals.

    * mean ± z s/√N (normal approximation, z the two-sided standard normal quantile of
      ``confidence``; s the sample standard deviation, ddof = 1);
    * percentile p: the estimate by linear interpolation between order statistics
      (``numpy.percentile``'s default); its interval [x_(l), x_(u)] between the order statistics
      of ranks l = F⁻¹(α/2) and u = F⁻¹(1 − α/2) + 1, F the Binomial(N, p/100) distribution,
      α = 1 − confidence: distribution-free, coverage >= ``confidence`` (Hahn & Meeker,
      "Statistical Intervals", 1991, §5.2). A rank outside 1 … N gives no bound (None).

    Args:
        values: the N sampled values, shape (N,), N >= 2 (finite).
        percentiles: the percentiles (0, 100), a sequence.
        confidence: the confidence level, in (0, 1).

    Returns:
        A JSON-ready dict: ``n``, ``mean``, ``std``, ``mean_ci`` [lo, hi], ``confidence``,
        ``percentiles``: {"5": {"value", "ci": [lo, hi]}, …}, ``min``, ``max``.

    Raises:
        ValueError: fewer than 2 values, non-finite values, a percentile or a confidence out of
            range.
    """
    x = np.sort(np.asarray(values, dtype=np.float64).reshape(-1))
    n = x.size
    if n < 2:
        raise ValueError(f"values: {n} given, allowed at least 2")
    if not np.all(np.isfinite(x)):
        raise ValueError("values: non-finite entries, allowed finite values only")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence = {confidence!r} is out of range: allowed (0, 1)")
    alpha = 1.0 - confidence
    z = NormalDist().inv_cdf(1.0 - alpha / 2.0)
    mean, std = float(x.mean()), float(x.std(ddof=1))
    half = z * std / math.sqrt(n)
    out_p = {}
    for p in percentiles:
        if not 0.0 < p < 100.0:
            raise ValueError(f"percentile = {p!r} is out of range: allowed (0, 100)")
        q = p / 100.0
        lo = binomial_quantile(alpha / 2.0, n, q)
        hi = binomial_quantile(1.0 - alpha / 2.0, n, q) + 1
        out_p[f"{p:g}"] = {
            "value": float(np.percentile(x, p)),
            "ci": [
                float(x[lo - 1]) if lo >= 1 else None,
                float(x[hi - 1]) if hi <= n else None,
            ],
        }
    return {
        "n": int(n),
        "mean": mean,
        "std": std,
        "mean_ci": [float(mean - half), float(mean + half)],
        "confidence": confidence,
        "percentiles": out_p,
        "min": float(x[0]),
        "max": float(x[-1]),
    }
