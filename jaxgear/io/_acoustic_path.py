"""The acoustic path of a housed case: what the acoustic objectives of ``jaxgear optimise``
("erp", "sound_power"; :mod:`optimise`'s :class:`~optimise.AcousticPath` and
:class:`~optimise.SurfaceRadiation`) run on, built from a pair or train case's ``[housing]``,
``[whine]`` and (sound power) ``[acoustics]`` as ``jaxgear run``'s housed whine builds them
(docs/acoustics.md, "Optimising for noise").

- :func:`housed_acoustics`: the housing body (condensed, cached), its outer skin with the named
  points and its :class:`jaxgear.acoustics.HousingAcoustics` (the skin's facets on the condensed
  coordinates); ``jaxgear run`` reads its housing outputs from the same three.
- :func:`case_acoustic_path`: the coupled path (the case's lumped 3D scene carries the
  housing) over the ``[whine]`` speeds, with its method and positions, at the orders of the
  mesh frequency below the housing's band limit (cut-off / :data:`HOUSING_BAND`) at every speed:
  the orders the run sums into its overall ERP and radiates.
- :func:`radiation_grid`: the frequencies ``[acoustics]`` computes R at (its ``band_Hz``, by
  default the orders' range, ``frequencies`` log-spaced), the run's and the objective's.
- :func:`case_radiation`: R of the housing's closed skin (:func:`fem_prep.housing.
  closed_outer_surface`, placed in the scene's frame as the run places it, with the run's
  microphones: one cache entry serves both) at that grid, and the map from the skin facets'
  normal velocities to the closed skin's vertices'.
- :func:`surface_sound_power`: the sound power (and the microphones' pressure) a surface's
  vertex velocities radiate over speeds and orders by ``[acoustics]``
  (:func:`surface_radiation`, then :func:`jaxgear.acoustics.radiated_sound_power`): what
  ``jaxgear run``'s ``acoustics/`` holds.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

import optimise as op
from fem_prep import acoustics as fa, schema as sc

from ..acoustics import HousingAcoustics, SoundPower, housing_acoustics, radiated_sound_power
from ..dynamics import DynamicModel
from ..scenes import band_speed_limit, housing_band_hz
from ._acoustics_table import AcousticsInputs, acoustics_of, parse_acoustics
from ._housing_table import HOUSING_BAND, housing_surface
from ._whine_table import whine_of

__all__ = [
    "FACTOR_BYTES",
    "HOUSING_BAND",
    "HousedAcoustics",
    "HousingBand",
    "case_acoustic_path",
    "case_radiation",
    "closed_skin",
    "housed_acoustics",
    "housing_band",
    "radiation_grid",
    "surface_radiation",
    "surface_sound_power",
]

#: the most memory (bytes) the radiation's factors L (G grid frequencies x n vertices x rank,
#: complex) may take in the design loop
FACTOR_BYTES = 2 * 1024**3


class HousedAcoustics(NamedTuple):
    """A housed case's housing: its :class:`~jaxgear.io.HousingBody` ``body``, its outer skin
    ``surface`` (:class:`fem_prep.housing.HousingSurface`, the named points on it), the skin's
    ``acoustics`` on the condensed coordinates (:class:`jaxgear.acoustics.HousingAcoustics`)
    and, once placed in a dynamic model (:func:`jaxgear.io.housed_run`), ``first``: the index
    of the first housing coordinate among the model's coordinates (the whine response's last
    axis; None: not placed, as :func:`housed_acoustics` returns it)."""

    body: object
    surface: object
    acoustics: HousingAcoustics
    first: int | None = None

    @property
    def band_limit_hz(self) -> float:
        """The highest frequency (Hz) whose response the condensed housing holds:
        cut-off / :data:`HOUSING_BAND`."""
        return housing_band_hz(self.body.condensed.cutoff_hz)

    def housing_coordinates(self, q) -> np.ndarray:
        """The housing's n_c condensed coordinates (..., n_c) of a placed housing's model
        coordinates ``q`` (..., N): its columns ``first`` to ``first + n_c``.

        Raises:
            ValueError: a housing not placed in a model (``first`` None; one line).
        """
        if self.first is None:
            raise ValueError("HousedAcoustics.first: None: allowed a housing placed in its "
                             "dynamic model (jaxgear.io.housed_run)")
        n_c = int(self.acoustics.K.shape[0])
        return np.asarray(q)[..., self.first : self.first + n_c]


class HousingBand(NamedTuple):
    """Where a housed case's model holds (:func:`housing_band`): ``cutoff_hz`` the housing's
    cut-off (Hz), ``band_hz`` its band f_b = cut-off / :data:`HOUSING_BAND` (Hz), ``mesh_order``
    the fastest mesh's order max_k |o_k| (its teeth per input turn), ``speed_limit`` Ω_b
    (rad/s), the highest input speed at which every mesh's order-1 frequency lies in the band."""

    cutoff_hz: float
    band_hz: float
    mesh_order: float
    speed_limit: float


def housing_band(case) -> HousingBand | None:
    """The band a housed case's model holds and its speed limit Ω_b (rad/s; a pair's: the
    pinion's) = 2π f_b / max_k |o_k| (:func:`jaxgear.scenes.band_speed_limit`), f_b = cut-off /
    :data:`HOUSING_BAND` (:func:`jaxgear.scenes.housing_band_hz`: the band the
    condensed housing's response holds, the whine's ``in_band``: docs/housing.md, "What the
    condensation keeps"), o_k each mesh's order (its teeth per input turn,
    :attr:`~jaxgear.io.Case.mesh_orders`). Above Ω_b the meshes excite the housing where its
    modes beyond the cut-off, left out of the model, count. From the case file alone (the
    housing is not condensed). None without ``[housing]``."""
    if case.housing is None:
        return None
    cutoff = float(case.housing.cutoff)
    order = max(abs(float(o)) for o in case.mesh_orders)
    return HousingBand(cutoff, housing_band_hz(cutoff), order,
                       band_speed_limit(cutoff, case.mesh_orders))


def housed_acoustics(case) -> HousedAcoustics | None:
    """The :class:`HousedAcoustics` of ``case``, None without ``[housing]``.

    Raises:
        SchemaError: a named point off the housing's outer surface (one line naming its key).
    """
    if case.housing is None:
        return None
    body = case.housing_body()  # the condensed housing from fem_prep's cache
    surface = housing_surface(case.housing, body)
    acoustics = housing_acoustics(body.condensed, surface, loss_factor=case.housing.loss_factor)
    return HousedAcoustics(body, surface, acoustics)


def _refuse(objective: str, why: str):
    return sc.fail("optimise", "objective", why, objective)


def _order_frequencies(case, speeds, orders) -> np.ndarray:
    """The frequencies (Hz, (S, O)) of the ``orders`` h of the mesh frequency at the pinion
    ``speeds`` (rad/s): h Ω z₁ / 2π, z₁ the teeth of the first mesh's driving gear (a train's
    input)."""
    f1 = np.asarray(speeds, dtype=float) * case.pairs[0].pinion.teeth / (2 * math.pi)
    return f1[:, None] * np.asarray(orders, dtype=float)[None, :]


def case_acoustic_path(case, objective: str = "erp", model=None,
                       housed: HousedAcoustics | None = None) -> op.AcousticPath:
    """The :class:`optimise.AcousticPath` of a housed pair or train case: its lumped 3D scene
    with the housing (coupled; ``model``: default :func:`jaxgear.io.build_dynamic_model` of the
    case), the ``[whine]`` speeds, method and positions per period, the orders h of the mesh
    frequency f_m = Ω z₁ / 2π (a train's: its first mesh's, z₁ its input's teeth) whose h f_m at
    the highest speed lies within the housing's band limit
    (:attr:`HousedAcoustics.band_limit_hz`).

    Args:
        case: a pair or train :class:`~jaxgear.io.Case` with ``[housing]`` and ``[whine]``.
        objective: the objective's name, for the errors.
        model, housed: already built (default: built here).

    Raises:
        SchemaError: no ``[housing]`` or ``[whine]``, a model that is not lumped, a train whose
            meshes have different frequencies (its span more than one period of the first), no
            order in the band (one line naming ``[optimise] objective`` and what is missing).
    """
    whine = whine_of(case)
    for table, given in (("housing", case.housing), ("whine", whine)):
        if given is None:
            raise _refuse(objective, f"runs on a housed gearbox's whine: the case needs "
                          f"[{table}] ([housing] and [whine] both; docs/acoustics.md)")
    if case.span_periods != 1:
        raise _refuse(objective, f"runs on a pair or on a train whose meshes share one mesh "
                      f"frequency (an idler train); this train's meshes repeat together every "
                      f"{case.span_periods} periods of the first")
    if model is None:
        from ._case_model import build_dynamic_model

        model, _ = build_dynamic_model(case)
    if not isinstance(model, DynamicModel):
        raise _refuse(objective, f"runs on a lumped scene carrying the housing: the case's model "
                      f"is a {type(model).__name__}")
    housed = housed_acoustics(case) if housed is None else housed
    speeds = np.asarray(whine.speeds, dtype=float)
    H = int(whine.method.harmonics)
    top = _order_frequencies(case, speeds.max()[None], range(1, H + 1))[0]
    f_mesh = float(top[0])
    orders = tuple(h for h in range(1, H + 1) if top[h - 1] <= housed.band_limit_hz)
    if not orders:
        raise _refuse(objective, f"no order of [whine] lies below the housing's band limit at "
                      f"every speed ({housed.band_limit_hz:.0f} Hz = cut-off / {HOUSING_BAND:g}, "
                      f"order 1 at {f_mesh:.0f} Hz): allowed a cut-off above 1.5 x the highest "
                      "order's frequency")
    return op.AcousticPath(model, housed.acoustics, speeds, orders, whine.method,
                           positions=whine.positions)


def radiation_grid(inputs: AcousticsInputs, frequencies) -> tuple[tuple[float, float], np.ndarray]:
    """The band (Hz) and the grid frequencies (Hz, (G,)) ``[acoustics]`` computes R at:
    ``band_Hz`` (default the range of ``frequencies``), ``frequencies`` of them log-spaced (one
    when the band is a single frequency)."""
    f = np.asarray(frequencies, dtype=float)
    band = inputs.band or (float(f.min()), float(f.max()))
    grid = (np.array([band[0]]) if inputs.frequencies == 1 or band[1] <= band[0]
            else np.geomspace(band[0], band[1], inputs.frequencies))
    return band, grid


def closed_skin(housed: HousedAcoustics):
    """The housing's outer skin closed over its openings (:func:`fem_prep.housing.
    closed_outer_surface`) and that closed surface placed in the scene's frame
    (x = R x_housing + t), as a :class:`fem_prep.acoustics.RadiatingSurface`."""
    from fem_prep.housing import closed_outer_surface

    body = housed.body
    skin = closed_outer_surface(body.mesh, housed.surface)
    R = np.asarray(body.housing.rotation, dtype=float)
    placed = fa.RadiatingSurface(skin.surface.vertices @ R.T + np.asarray(body.offset, float),
                                 skin.surface.triangles)
    return skin, placed


def case_radiation(case, path: op.AcousticPath, housed: HousedAcoustics | None = None,
                   progress: bool = False) -> op.SurfaceRadiation:
    """The :class:`optimise.SurfaceRadiation` of a housed case's ``[acoustics]`` for the
    objective "sound_power" on ``path`` (:func:`case_acoustic_path`): R of the closed skin by
    the table's method (``bem`` or ``erp-only``), fluid and rank at :func:`radiation_grid` of the
    path's order frequencies (read from / written to fem_prep's cache as ``jaxgear run`` does),
    and the vertex map V = (N_v Φ)(N_f Φ)⁺ from the skin facets' mean normal velocities to the
    closed skin's vertex normal velocities (exact on the condensed coordinates' span: N_f Φ of
    full column rank).

    Raises:
        SchemaError: no ``[acoustics]``; a ``band_Hz`` that does not span the path's
            frequencies; factors over :data:`FACTOR_BYTES` (naming ``rank``); a skin whose facets
            do not determine its vertices' motion (one line each).
    """
    inputs = acoustics_of(case, progress)
    if inputs is None:
        raise _refuse("sound_power", "radiates by the case's [acoustics] table (its method, band "
                      "and grid; e.g. [acoustics] method = 'bem'): the case has none")
    housed = housed_acoustics(case) if housed is None else housed
    freq = _order_frequencies(case, path.speeds, path.orders)
    band, grid = radiation_grid(inputs, freq)
    if freq.min() < grid[0] * (1 - 1e-9) or freq.max() > grid[-1] * (1 + 1e-9):
        raise sc.fail("acoustics", "band_Hz", "must span the order frequencies the objective "
                      f"sound_power radiates at, [{freq.min():.6g}, {freq.max():.6g}] Hz",
                      list(band))
    skin, placed = closed_skin(housed)
    n = int(placed.n_vertices)
    rank = n if inputs.rank is None else min(inputs.rank, n)
    need = len(grid) * n * rank * 16
    if need > FACTOR_BYTES:
        allowed = max(1, FACTOR_BYTES // (16 * len(grid) * n))
        raise sc.fail("acoustics", "rank", f"the radiation's factors ({len(grid)} frequencies x "
                      f"{n} vertices x rank {rank}) take {need / 1024**3:.3g} GiB in the design "
                      f"loop: allowed rank <= {allowed} (or fewer frequencies)",
                      sc.MISSING if inputs.rank is None else inputs.rank)
    body = housed.body
    vertices = np.asarray(skin.normal_operator @ body.condensed.recovery)  # (n, n_c)
    facets = np.asarray(housed.acoustics.normal_map)  # (F, n_c)
    vertex_map = np.linalg.lstsq(facets.T, vertices.T, rcond=None)[0].T  # (n, F)
    err = np.linalg.norm(vertex_map @ facets - vertices) / max(np.linalg.norm(vertices), 1e-300)
    if not err <= 1e-6:
        raise _refuse("sound_power", f"the housing skin's {facets.shape[0]} facets do not "
                      f"determine its {facets.shape[1]} condensed coordinates' motion (relative "
                      f"residual {err:.2g}): allowed a finer [housing] mesh_size_mm")
    rr = surface_radiation(placed, grid, inputs, progress)
    return op.SurfaceRadiation(jnp.asarray(vertex_map), jnp.asarray(rr.factors), grid)


def surface_radiation(surface, grid, inputs: AcousticsInputs, progress: bool = False):
    """The :class:`fem_prep.acoustics.RadiationResistance` of ``surface`` at the ``grid``
    frequencies (Hz, (G,)) by ``[acoustics]``'s method, fluid and rank, with the pressure
    transfer to its microphones (read from / written to fem_prep's cache,
    :func:`fem_prep.acoustics.radiation_resistance`: one BEM solve per grid frequency)."""
    mics = inputs.microphones
    points = np.array([p for _, p in mics]) if mics else None
    return fa.radiation_resistance(surface, grid, inputs.fluid, inputs.method, rank=inputs.rank,
                                   cache=inputs.cache, progress=progress, points=points)


def surface_sound_power(surface, velocities, speeds, orders, inputs, *, frequencies=None,
                        progress: bool = False) -> SoundPower:
    """The sound power a vibrating surface radiates at each speed and order, by a case's
    ``[acoustics]`` table: the radiation operators of its method at :func:`radiation_grid` of
    the orders' frequencies (:func:`surface_radiation`, cached), then
    :func:`jaxgear.acoustics.radiated_sound_power` (W = vᴴ R v interpolated log-log between the
    grid frequencies, L_W, L_WA, the overall sums and the microphones' pressure). What
    ``jaxgear run``'s ``[acoustics]`` writes (``acoustics/``) and the sizing's sound stage
    ranks.

    Args:
        surface: the :class:`fem_prep.acoustics.RadiatingSurface` (m): closed for ``bem``
            (:func:`closed_skin`), a flat panel for ``rayleigh``.
        velocities: ``(S, O, n)`` complex normal velocity amplitudes at the surface's vertices
            (m/s, one-sided, v(t) = Re v e^{iωt}, positive outward).
        speeds: ``(S,)`` input speeds (rad/s, > 0).
        orders: ``(O,)`` the orders (> 0): order o at speed Ω sounds at o Ω / 2π Hz unless
            ``frequencies`` says otherwise.
        inputs: :class:`AcousticsInputs` (:func:`acoustics_of`) or the raw ``[acoustics]``
            table (a dict, read by :func:`parse_acoustics`).
        frequencies: ``(S, O)`` Hz of each order at each speed (a whine sweep's
            ``frequency[:, None] * orders[None, :]``), or None.
        progress: progress bars over the radiation solves.

    Returns:
        The :class:`jaxgear.acoustics.SoundPower` (its ``band`` the table's ``band_Hz`` or the
        orders' range).

    Raises:
        TypeError: a surface that is not a RadiatingSurface, a table of another type.
        ValueError: shapes that do not fit, a speed, order or frequency ≤ 0 or not finite (one
            line each).
    """
    if not isinstance(surface, fa.RadiatingSurface):
        raise TypeError(f"surface_sound_power: surface = {type(surface).__name__}, allowed a "
                        "fem_prep.acoustics.RadiatingSurface")
    if isinstance(inputs, dict):
        inputs = parse_acoustics(inputs, progress)
    if not isinstance(inputs, AcousticsInputs):
        raise TypeError(f"surface_sound_power: table = {inputs!r}, allowed AcousticsInputs or a dict")
    speeds = np.asarray(speeds, dtype=float).reshape(-1)
    orders = np.asarray(orders, dtype=float).reshape(-1)
    v = np.asarray(velocities)
    S, O, n = len(speeds), len(orders), surface.n_vertices
    if v.shape != (S, O, n):
        raise ValueError(f"surface_sound_power: velocities = {v.shape}, allowed (S, O, n) = "
                         f"({S}, {O}, {n}) (speeds, orders, the surface's vertices)")
    for what, x in (("speeds", speeds), ("orders", orders)):
        if x.size == 0 or not np.all(np.isfinite(x)) or x.min() <= 0:
            raise ValueError(f"surface_sound_power: {what} = {x.tolist()}, allowed finite values > 0")
    f = (orders[None, :] * speeds[:, None] / (2 * np.pi) if frequencies is None
         else np.asarray(frequencies, dtype=float))
    if f.shape != (S, O) or not np.all(np.isfinite(f)) or f.min() <= 0:
        raise ValueError(f"surface_sound_power: frequencies {f.shape}, allowed (S, O) = ({S}, {O}) "
                         "finite values > 0 (Hz)")
    band, grid = radiation_grid(inputs, f)  # the grid the acoustic objectives radiate at too
    rr = surface_radiation(surface, grid, inputs, progress)
    return radiated_sound_power(v, f, rr, band=band)
