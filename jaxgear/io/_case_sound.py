"""The sound of a housed case (docs/housing.md, "In jaxgear run"; docs/acoustics.md): its gear
whine over the ``[whine]`` speeds on the case's dynamic model (the housing a body of its lumped
3D scene, or a planetary stage's on its mount), the housing's condensed coordinates of that
response recovered on its outer skin, the skin's equivalent radiated power (ERP) per order and
speed and, with ``[acoustics]``, the sound power the closed skin radiates. What ``jaxgear run``
writes into ``whine/housing.*`` and ``acoustics/`` (its writers, :mod:`jaxgear.cli`) and what
the sizing's sound stage ranks (``jaxgear size --sound``).

- :func:`case_sound`: the one call, a case to its :class:`CaseSound` (the whine, the ERP, the
  sound power).
- :func:`case_whine`: a case's dynamic model, its housing placed in it
  (:class:`~jaxgear.io.HousedAcoustics`) and its whine response.
- :func:`housed_run`, :func:`housed_erp`, :func:`housed_radiation`: the steps, for a response
  solved elsewhere (a gearbox's housing).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..acoustics import SoundPower, housing_vibration, total_level
from ..dynamics import whine_response
from ..planetary import PlanetaryModel
from ..scenes import HOUSING_BAND
from ._acoustic_path import HousedAcoustics, closed_skin, housed_acoustics, surface_sound_power
from ._acoustics_table import AcousticsInputs, acoustics_of
from ._case_file import SchemaError
from ._case_model import build_dynamic_model
from ._whine_table import whine_of

__all__ = [
    "CaseSound",
    "HousedErp",
    "HousedRadiation",
    "case_sound",
    "case_whine",
    "housed_erp",
    "housed_radiation",
    "housed_run",
]


def housed_run(case, model) -> HousedAcoustics | None:
    """The :class:`~jaxgear.io.HousedAcoustics` of ``case`` placed in its dynamic model
    ``model`` (a lumped scene carrying the housing, or a
    :class:`~jaxgear.planetary.PlanetaryModel` whose housing's coordinates follow the stage's):
    what a housed whine's sound needs, gathered before the whine is solved (the named points
    checked first), its ``first`` the index of the first housing coordinate among the model's
    coordinates. None without ``[housing]``.

    Raises:
        SchemaError: a named point off the housing's outer surface (one line naming its key).
    """
    housed = housed_acoustics(case)  # the condensed housing from fem_prep's cache
    if housed is None:
        return None
    body = housed.body
    if isinstance(model, PlanetaryModel):  # a housed stage's: the housing's h follow the stage's
        first = len(model.coordinates()) - model.mount().size
    else:
        first = model.scene.structure.node(f"housing {body.condensed.seat_names[0]}")
    return housed._replace(first=int(first))


class HousedErp(NamedTuple):
    """The equivalent radiated power of a housed whine (:func:`housed_erp`), over S speeds and
    the k orders of the whine above the mean.

    Attributes:
        orders: (k,) the orders (of the first mesh's frequency).
        keep: (K,) bool, which of the whine's K orders they are (all but the mean).
        frequency: (S, k) Hz of each order at each speed.
        vibration: the skin's :class:`~jaxgear.acoustics.HousingResponse` (its coordinates
            (S, k, n_c), facets' normal velocity (S, k, F) and named points' (S, k, P), m/s).
        power: (S, k) ERP (W); level: (S, k) its L_W (dB re 1 pW).
        band: the band limit (Hz), cut-off / :data:`~jaxgear.scenes.HOUSING_BAND`.
        in_band: (S, k) whether each order's frequency is at most ``band``.
        overall_w: (S,) W, overall_db: (S,) dB re 1 pW, the sums over the orders in the band
            (overall_db NaN at a speed with none).
    """

    orders: np.ndarray
    keep: np.ndarray
    frequency: np.ndarray
    vibration: object
    power: np.ndarray
    level: np.ndarray
    band: float
    in_band: np.ndarray
    overall_w: np.ndarray
    overall_db: np.ndarray

    def peak(self) -> int | None:
        """The speed index of the largest overall ERP (None: no order in the band)."""
        if not self.in_band.any():
            return None
        return int(np.nanargmax(np.where(np.isfinite(self.overall_db), self.overall_db,
                                         -np.inf)))


def housed_erp(run: HousedAcoustics, w) -> HousedErp:
    """The housing's ERP of the whine response ``w`` of the housed model (a
    :class:`~jaxgear.dynamics.WhineResponse`: its coordinates (S, K, N), one-sided, q(t) = Re
    q e^{iωt}): its condensed coordinates recovered on the outer skin, v_n = iω N Φ q
    (:func:`jaxgear.acoustics.housing_vibration`), ERP = ½ ρ c ∫ |v_n|² dS per order (exact
    for the elements' shape functions; Fritze, Marburg & Hardtke, Acta Acustica united with
    Acustica 95, 2009), the overall the sum over the orders in the band (frequency <= cut-off /
    1.5, :func:`jaxgear.scenes.housing_band_hz`: the band the condensed housing's response
    holds; docs/housing.md). The mean (order 0) moves the housing statically and is left
    out. ``run``: the housing placed in the model (:func:`housed_run`).

    Raises:
        ValueError: a housing not placed in a model (its ``first`` None; one line).
    """
    f1 = np.asarray(w.frequency, dtype=float)
    orders_all = np.asarray(w.orders, dtype=float)
    keep = orders_all > 0  # the mean moves the housing statically: no velocity
    orders = orders_all[keep]
    freq = f1[:, None] * orders[None, :]  # (S, k) Hz
    q = run.housing_coordinates(np.asarray(w.coordinates)[:, keep])
    r = housing_vibration(run.acoustics, q, freq)
    power = np.asarray(r.power, dtype=float)  # (S, k) W
    band = run.band_limit_hz  # the housing's rule
    in_band = freq <= band
    overall_db = np.asarray(total_level(np.where(in_band, power, 0.0)), dtype=float)
    return HousedErp(orders, keep, freq, r, power, np.asarray(r.level, dtype=float), band,
                     in_band, np.where(in_band, power, 0.0).sum(axis=1),
                     np.where(in_band.any(axis=1), overall_db, np.nan))


class HousedRadiation(NamedTuple):
    """What a housed whine radiates (:func:`housed_radiation`): ``surface`` the housing's outer
    skin closed over its bores in the scene's frame (a :class:`fem_prep.acoustics.
    RadiatingSurface`, m), ``velocity`` (S, k, n) its vertices' complex outward normal velocity
    (m/s, one-sided, v(t) = Re v e^{iωt}), at the ``speeds`` (S,) rad/s and the ``orders`` (k,)
    in the housing's band at every speed, of ``frequency`` (S, k) Hz."""

    surface: object
    velocity: np.ndarray
    speeds: np.ndarray
    orders: np.ndarray
    frequency: np.ndarray


def housed_radiation(run: HousedAcoustics, w, erp: HousedErp) -> HousedRadiation:
    """The radiating skin of the whine response ``w`` of the housed model (its ERP ``erp``,
    :func:`housed_erp`): the outer skin closed over its bores
    (:func:`fem_prep.housing.closed_outer_surface`) placed in the scene's frame (x = R
    x_housing + t: the microphones are in the scene's frame, as the named points), its
    vertices' normal velocity v = iω N_v Φ q of the housing's condensed coordinates q, at the
    orders in the band at every speed. What ``jaxgear run``'s ``[acoustics]`` and the sizing's
    sound stage radiate (:func:`surface_sound_power`).

    Raises:
        SchemaError: no order in the band at every speed (one line).
        ValueError: a housing not placed in a model (its ``first`` None; one line).
    """
    every = erp.in_band.all(axis=0)
    orders, freq = erp.orders[every], erp.frequency[:, every]
    if not orders.size:
        raise SchemaError(
            f"[acoustics]: no order of [whine] lies below the housing's band limit at every "
            f"speed ({run.band_limit_hz:.0f} Hz = cut-off / "
            f"{HOUSING_BAND:g}): allowed a cut-off above 1.5 x the highest order's frequency"
        )
    q = run.housing_coordinates(np.asarray(w.coordinates)[:, erp.keep][:, every])
    skin, placed = closed_skin(run)  # the skin housed_run found, closed, in the scene's frame
    velocity = 1j * 2 * np.pi * freq[..., None] * (
        q @ (skin.normal_operator @ run.body.condensed.recovery).T)
    return HousedRadiation(placed, velocity, np.asarray(w.speed, dtype=float), orders, freq)


def case_whine(case, inputs=None):
    """The whine of ``case`` over its ``[whine]`` speeds (``inputs``: its
    :class:`~jaxgear.io.WhineInputs`, default read here): (the case's dynamic model,
    :func:`build_dynamic_model`; its ``[housing]`` placed in it (:func:`housed_run`) or None; the
    :class:`~jaxgear.dynamics.WhineResponse` of :func:`jaxgear.dynamics.whine_response` by
    the table's method and positions per period), as ``jaxgear run`` solves it. A housing's
    named points are checked before the whine is solved.

    Raises:
        ValueError: a case without ``[whine]``, a case whose model kind has no gear whine (one
            line each).
    """
    inputs = whine_of(case) if inputs is None else inputs
    if inputs is None:
        raise SchemaError("[whine]: the case has none: allowed a case with a [whine] table "
                          "(its speeds; docs/whine.md)")
    model, _ = build_dynamic_model(case)
    if not model.whine_methods:  # what the model kind declares
        raise ValueError(
            f"[whine]: the case's model is a {type(model).__name__}, which has no gear whine: "
            "allowed a lumped scene (torsional or lumped 3D), a pair with condensed bodies or "
            "a planetary stage's"
        )
    housed = housed_run(case, model)  # [housing]: its points checked before the whine
    w = whine_response(model, np.asarray(inputs.speeds), inputs.method,
                       positions=inputs.positions)
    return model, housed, w


class CaseSound(NamedTuple):
    """The sound of a housed case (:func:`case_sound`), over the S ``[whine]`` speeds.

    Attributes:
        model: the case's dynamic model (:func:`build_dynamic_model`).
        housed: its housing placed in it (:class:`~jaxgear.io.HousedAcoustics`,
            :func:`housed_run`).
        whine: the :class:`~jaxgear.dynamics.WhineResponse` (speeds ``whine.speed`` (S,),
            rad/s, the input's; its orders ``whine.orders``).
        erp: the housing skin's :class:`HousedErp` per order and speed (W, dB re 1 pW) and
            overall (``erp.overall_db`` (S,)).
        radiation: the closed skin's :class:`HousedRadiation` (None: no sound power asked).
        sound_power: the :class:`jaxgear.acoustics.SoundPower` it radiates by the case's
            ``[acoustics]`` (L_W per order (S, O) and overall (S,), dB re 1 pW; None: not
            asked).
    """

    model: object
    housed: HousedAcoustics
    whine: object
    erp: HousedErp
    radiation: HousedRadiation | None = None
    sound_power: SoundPower | None = None

    def with_sound_power(self, inputs: AcousticsInputs, progress: bool = False) -> CaseSound:
        """This sound with the radiated sound power by ``inputs`` (a case's ``[acoustics]``,
        :func:`acoustics_of`): the closed skin's velocity (:func:`housed_radiation`) radiated
        by :func:`surface_sound_power` (one BEM solve per grid frequency, cached).

        Raises:
            SchemaError: no order in the housing's band at every speed (one line).
        """
        h = housed_radiation(self.housed, self.whine, self.erp)
        p = surface_sound_power(h.surface, h.velocity, h.speeds, h.orders, inputs,
                                frequencies=h.frequency, progress=progress)
        return self._replace(radiation=h, sound_power=p)


def case_sound(case, *, sound_power: bool | None = None, progress: bool = False) -> CaseSound:
    """The sound of a housed pair, train or planetary case, as ``jaxgear run`` computes it: its
    whine over the ``[whine]`` speeds (:func:`case_whine`), the housing skin's ERP per order
    and speed and overall over the orders in the housing's band (:func:`housed_erp`: what
    ``whine/housing.json`` holds) and, with ``sound_power``, the sound power the closed skin
    radiates by the case's ``[acoustics]`` (:meth:`CaseSound.with_sound_power`: what
    ``acoustics/sound_power.json`` holds). The sizing's sound stage runs each candidate's
    housed case through it.

    Args:
        case: a :class:`~jaxgear.io.Case` with ``[housing]`` and ``[whine]``.
        sound_power: True: the radiated sound power (the case needs ``[acoustics]``); False:
            the ERP only; None (default): the sound power where the case has ``[acoustics]``.
        progress: progress bars over the radiation solves.

    Returns:
        The :class:`CaseSound`.

    Raises:
        SchemaError: a case without ``[housing]`` or ``[whine]``, or without ``[acoustics]``
            where ``sound_power`` is True; a named point off the housing; no order in the
            housing's band at every speed (with the sound power); one line each, before the
            whine is solved where it can be told from the case file.
        ValueError: a case whose model kind has no gear whine (one line).
    """
    if case.housing is None:
        raise SchemaError("[housing]: the case has none: case_sound needs a housed case "
                          "([housing] and [whine]; docs/housing.md)")
    if whine_of(case) is None:
        raise SchemaError("[whine]: the case has none: case_sound needs a housed case's whine "
                          "([housing] and [whine]; docs/whine.md)")
    table = acoustics_of(case, progress) if sound_power in (None, True) else None
    if sound_power is True and table is None:
        raise SchemaError("[acoustics]: the case has none: case_sound(sound_power=True) "
                          "radiates by its method, band and grid (docs/acoustics.md)")
    model, housed, w = case_whine(case)
    sound = CaseSound(model, housed, w, housed_erp(housed, w))
    return sound if table is None else sound.with_sound_power(table, progress)
