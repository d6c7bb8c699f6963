"""The ring gear's model in a planetary case file: ``[planetary.ring] model`` and ``body``
(docs/planetary.md, "A flexible ring gear"), mapped to :class:`~jaxgear.planetary.RigidRing`,
:class:`~jaxgear.planetary.CondensedRing` or :class:`~jaxgear.planetary.CraigBamptonRing`.

.. code-block:: toml

    [planetary.ring]
    torsional_stiffness_Nm_per_rad = 1e12
    model = "condensed"                # or "rigid" (the default)
    body = "seq-ring"                  # a ring body file (fem_prep) or an embedded ring's name
    dynamics = "modal"                 # the ring in the sweep: "quasi-static" (the default),
                                       # "mass", "modal" or "craig-bampton"
    modes = 24                         # "modal": the ring's modes kept, 1..2 Z (default 24);
                                       # "craig-bampton": its fixed-interface modes kept
                                       # (default: every coupled one)
    integration_modes = 24             # "craig-bampton" only: the Craig-Bampton ring's modes
                                       # integrated in the sweep, 1..2 Z + modes (default 24)

The ring body's tooth stations must be the ring gear's teeth and, with ``[[gears]]``, its root
radius the ring gear's within :data:`ROOT_TOLERANCE`; refused in one line before any work.

``dynamics`` (:data:`RING_DYNAMICS`) is how the condensed ring enters the dynamic-factor sweep of
``jaxgear run`` and ``jaxgear sweep``: ``"quasi-static"`` the massless ring (its compliance in
series with the ring meshes at every step), ``"mass"`` with its stations' (Guyan) mass and modal
damping at the run's ratio (its nodal-diameter modes respond), ``"modal"`` the same ring in its
``modes`` lowest modes plus the static correction of the others
(:class:`~jaxgear.planetary.CondensedRing` ``modes``), ``"craig-bampton"`` the condensed ring reduced onto
its stations and its ``modes`` lowest fixed-interface modes that couple to them
(:class:`~jaxgear.planetary.CraigBamptonRing`: the ring's own dynamics inside the stations), integrated in
its ``integration_modes`` lowest modes plus the static correction of the others. The count of
coupled fixed-interface modes is known once the ring is condensed: ``modes`` is checked at
parse time against the fixed-interface DOFs of the body's condensation (Z (3 n_axial - 2) +
its modes) and, if the ring couples fewer, refused in one line when the sweep builds the ring.
"""

from __future__ import annotations

import abc
import dataclasses

import fem_prep
from fem_prep import schema as sc

from ..planetary import AbstractRingModel, CondensedRing, CraigBamptonRing, RigidRing
from ._sections import in_range

__all__ = ["RING_DYNAMICS", "RING_MODELS", "CondensedRingSpec", "RigidRingSpec", "RingModelSpec",
           "parse_ring_model"]

#: ``[planetary.ring] modes`` when ``dynamics = "modal"`` does not give it, and
#: ``integration_modes`` when ``dynamics = "craig-bampton"`` does not
DEFAULT_RING_MODES = 24
#: fixed-interface modes whose eigenvalues differ by at most this share are a pair (one nodal
#: diameter's two orientations), which ``modes`` may not split
PAIR = 1e-6
#: the largest relative difference between the ring body's and the ring gear's root radius
ROOT_TOLERANCE = 0.02


class RingModelSpec(abc.ABC):
    """How the case's ring deforms (``[planetary.ring] model``)."""

    #: whether the ring is a flexible body (its outputs: ``jaxgear run``'s ``ring`` section)
    flexible: bool = False

    @abc.abstractmethod
    def ring(self, with_mass: bool = False) -> AbstractRingModel:
        """The library's ring model (with the stations' mass for the dynamics if asked)."""

    @abc.abstractmethod
    def dynamic_ring(self) -> AbstractRingModel:
        """The ring model of the dynamic-factor sweep (``dynamics``, module docstring)."""

    @abc.abstractmethod
    def summary(self) -> dict:
        """The ring model's keys for ``sweep.json`` and ``summary.json``."""

    @abc.abstractmethod
    def words(self) -> str:
        """The ring model in a few words (plot titles, printed lines)."""


@dataclasses.dataclass(frozen=True)
class RigidRingSpec(RingModelSpec):
    """The lumped model's rigid ring (the default)."""

    def ring(self, with_mass=False):
        return RigidRing()

    def dynamic_ring(self):
        return RigidRing()

    def summary(self):
        return {"model": "rigid"}

    def words(self):
        return "rigid ring"


def _craig_bampton(spec, st) -> CraigBamptonRing:
    """The sweep's :class:`~jaxgear.planetary.CraigBamptonRing`; ``modes`` or ``integration_modes`` beyond
    what the condensed ring has refused in one line (module docstring)."""
    m = len(st.interior_eigenvalues)
    if spec.modes is not None and spec.modes > m:
        raise sc.fail("planetary.ring", "modes", f"out of range, allowed [1, {m}] (the fixed-"
                      f"interface modes that ring body {spec.body.name!r} couples to its "
                      "stations)", spec.modes)
    lam = st.interior_eigenvalues
    if spec.modes is not None and spec.modes < m and (
            lam[spec.modes] - lam[spec.modes - 1] <= PAIR * lam[spec.modes]):
        raise sc.fail("planetary.ring", "modes", "splits a pair of equal-frequency fixed-"
                      f"interface modes (a nodal-diameter pair; allowed {spec.modes - 1} or "
                      f"{spec.modes + 1})", spec.modes)
    coords = 2 * st.compliance.shape[0] + (m if spec.modes is None else spec.modes)
    if spec.integration_modes > coords:
        raise sc.fail("planetary.ring", "integration_modes", f"out of range, allowed [1, "
                      f"{coords}] (2 x the stations + the fixed-interface modes kept)",
                      spec.integration_modes)
    return CraigBamptonRing.from_stations(st, spec.modes, spec.integration_modes)


#: ``[planetary.ring] dynamics``: the name -> (the sweep's ring from the spec and its
#: :class:`fem_prep.RingStations`, its words) (module docstring)
_DYNAMICS = {
    "quasi-static": (lambda spec, st: CondensedRing(st.compliance), lambda spec: "massless"),
    "mass": (lambda spec, st: CondensedRing(st.compliance, st.mass), lambda spec: "with mass"),
    "modal": (lambda spec, st: CondensedRing(st.compliance, st.mass, spec.modes),
              lambda spec: f"{spec.modes} modes"),
    "craig-bampton": (_craig_bampton, lambda spec: "Craig-Bampton, " + (
        "all coupled" if spec.modes is None else str(spec.modes)) + " fixed-interface modes, "
        f"{spec.integration_modes} modes integrated"),
}
#: ``[planetary.ring] dynamics``: how a condensed ring enters the sweep (module docstring)
RING_DYNAMICS = tuple(_DYNAMICS)


@dataclasses.dataclass(frozen=True)
class CondensedRingSpec(RingModelSpec):
    """A flexible ring: its body (:class:`fem_prep.RingBody`) named by ``body``, condensed on its
    tooth stations once and then read from the fem_prep cache (:func:`fem_prep.ring_stations`).
    """

    body: fem_prep.RingBody
    source: str
    dynamics: str = "quasi-static"
    modes: int | None = None
    integration_modes: int | None = None
    flexible = True

    def stations(self) -> fem_prep.RingStations:
        return fem_prep.ring_stations(self.body)

    def ring(self, with_mass=False):
        st = self.stations()
        return CondensedRing(st.compliance, st.mass if with_mass else None)

    def dynamic_ring(self):
        return _DYNAMICS[self.dynamics][0](self, self.stations())

    def summary(self):
        out = {"model": "condensed", "body": self.source, "dynamics": self.dynamics}
        if self.modes is not None:
            out["modes"] = self.modes
        if self.integration_modes is not None:
            out["integration_modes"] = self.integration_modes
        return out

    def words(self):
        return f"condensed ring {self.source} ({_DYNAMICS[self.dynamics][1](self)})"


def _rigid(t, where: str, z_r: int, root_radius: float | None) -> RingModelSpec:
    for key in ("body", "dynamics", "modes", "integration_modes"):
        if key in t.given:
            raise sc.fail(where, key, 'allowed only with model = "condensed"', getattr(t, key))
    return RigidRingSpec()


def _condensed(t, where: str, z_r: int, root_radius: float | None) -> RingModelSpec:
    if t.body is None:
        raise sc.fail(where, "body", "missing required key")
    source = t.body
    try:
        body = fem_prep.load_ring_body(source)
    except FileNotFoundError as err:
        raise sc.fail(where, "body", str(err).split(" (")[0] + " (allowed: a ring body file or "
                      f"an embedded ring: {', '.join(fem_prep.embedded_rings())})",
                      source) from None
    except ValueError as err:
        raise sc.SchemaError(f"[{where}] body = {source!r}: {err}") from None
    teeth = body.condensation.teeth
    if teeth != z_r:
        raise sc.fail(where, "body", f"ring body {body.name!r} has {teeth} tooth stations "
                      f"([condensation] teeth); the ring gear has {z_r} teeth (allowed: equal)",
                      source)
    if root_radius is not None:
        diff = abs(body.root_radius - root_radius) / root_radius
        if diff > ROOT_TOLERANCE:
            raise sc.fail(
                where, "body",
                f"ring body {body.name!r} root_radius_mm = {body.root_radius * 1e3:.6g} differs "
                f"from the ring gear's root radius {root_radius * 1e3:.6g} mm by "
                f"{100 * diff:.3g} % (allowed: within {100 * ROOT_TOLERANCE:g} %)", source)
    dynamics = t.dynamics or "quasi-static"
    modes, integration = _MODE_KEYS.get(dynamics, _no_modes)(t, where, body)
    return CondensedRingSpec(body, source, dynamics, modes, integration)


def _count(t, key: str, where: str, default, top: int, note: str):
    """``modes`` or ``integration_modes`` (an integer, the section's) in [1, ``top``] (the ring
    body's), ``default`` where not given."""
    v = getattr(t, key)
    return default if v is None else in_range(where, key, v, f"[1, {top}]", note)


def _no_modes(t, where: str, body) -> tuple[None, None]:
    if t.modes is not None:
        raise sc.fail(where, "modes", 'allowed only with dynamics = "modal" or "craig-bampton"',
                      t.modes)
    if t.integration_modes is not None:
        raise sc.fail(where, "integration_modes", 'allowed only with dynamics = "craig-bampton"',
                      t.integration_modes)
    return None, None


def _modal_modes(t, where: str, body) -> tuple[int, None]:
    if t.integration_modes is not None:
        raise sc.fail(where, "integration_modes", 'allowed only with dynamics = "craig-bampton"',
                      t.integration_modes)
    teeth = body.condensation.teeth
    return _count(t, "modes", where, DEFAULT_RING_MODES, 2 * teeth,
                  f" (2 x the ring body's {teeth} tooth stations)"), None


def _craig_bampton_modes(t, where: str, body) -> tuple[int | None, int]:
    c = body.condensation
    top = c.teeth * (3 * c.axial_master_nodes - 2) + c.modes  # the fixed-interface DOFs
    modes = _count(t, "modes", where, None, top, f" (the fixed-interface DOFs of ring body "
                   f"{body.name!r}: its {c.teeth} stations' axial masters and {c.modes} modes)")
    coords = 2 * c.teeth + (top if modes is None else modes)
    integration = _count(t, "integration_modes", where, min(DEFAULT_RING_MODES, coords), coords,
                         f" (2 x the {c.teeth} stations + the fixed-interface modes)")
    return modes, integration


#: ``dynamics`` -> the parser of its ``modes`` and ``integration_modes`` (the others: none)
_MODE_KEYS = {"modal": _modal_modes, "craig-bampton": _craig_bampton_modes}


#: ``[planetary.ring] model``: the name → its parser (the ring's section, where, z_r, root
#: radius (m) or None)
RING_MODELS = {"rigid": _rigid, "condensed": _condensed}


def parse_ring_model(t, z_r: int, root_radius: float | None) -> RingModelSpec:
    """The ring model of ``[planetary.ring]`` (module docstring; ``t`` its
    :class:`~jaxgear.io._planetary_table.RingSection`, whose keys are typed), validated
    against the ring body (one-line :class:`~fem_prep.schema.SchemaError`)."""
    return RING_MODELS[t.model](t, "planetary.ring", z_r, root_radius)
