"""The case file's ``[acoustics]`` table: the sound a housed case radiates (docs/acoustics.md,
"Outputs"), checked whole and mapped to the radiation method objects here only.

Keys (file units; ranges as checked)::

    [acoustics]
    method = "bem"              # "bem" (exterior BEM on the closed housing skin, the default),
                                # "rayleigh" (a flat panel in a rigid baffle) or "erp-only"
                                # (every facet a plane wave: radiation efficiency 1)
    band_Hz = [100.0, 4000.0]   # the band R is computed over, (0, 1e5] Hz, max > min;
                                # default: the orders' frequencies over the speeds
    frequencies = 24            # R at this many frequencies, log-spaced over the band,
                                # [1, 2000]; default 24; between them the power is
                                # interpolated log-log (jaxgear.acoustics.radiated_power_at)
    rank = 64                   # the radiation modes kept (R ~ L L^H), [1, 1e6]; default all
    cache = true                # R read from / written to fem_prep's cache; default true
    density_kg_m3 = 1.21        # the fluid, (0, 1e4]; default air at 20 °C
    sound_speed_m_s = 343.0     # (0, 1e5]
    [[acoustics.microphones]]   # field points for the pressure spectra (not with erp-only)
    name = "front"              # default "mic<k>"
    position_mm = [150.0, -1000.0, 80.0]   # in the radiating surface's frame (mm)

``jaxgear run`` on a housed case writes ``acoustics/``: the sound power level against speed per
order and overall (linear and A-weighted, PNG, CSV, JSON), the microphone spectra and the surface
map of the radiated intensity (PNG and VTU): :func:`jaxgear.cli`'s ``acoustic_outputs``.
"""

from __future__ import annotations

from typing import ClassVar, Literal, NamedTuple

import pydantic

from fem_prep import acoustics as fa, schema as sc

from ._sections import Section, Text, number, number_list

__all__ = ["ACOUSTICS_KEYS", "ACOUSTICS_METHODS", "AcousticsInputs", "AcousticsSection",
           "Microphone", "acoustics_of",
           "check_band", "parse_acoustics", "parse_case_acoustics"]

WHERE = "acoustics"
#: ``[acoustics] method`` names
ACOUSTICS_METHODS = {"bem": fa.BEM, "rayleigh": fa.Rayleigh, "erp-only": fa.ERP}


class AcousticsInputs(NamedTuple):
    """``[acoustics]`` in SI: the ``method`` (a :class:`fem_prep.acoustics.RadiationMethod`),
    ``band`` ((lo, hi) Hz or None: the orders' range), ``frequencies`` (grid size), ``rank``
    (None: all), ``cache``, the ``fluid`` and ``microphones`` ((name, (x, y, z) m), ...)."""

    method: fa.RadiationMethod
    band: tuple[float, float] | None
    frequencies: int
    rank: int | None
    cache: bool
    fluid: fa.Fluid
    microphones: tuple[tuple[str, tuple[float, float, float]], ...]


class Microphone(Section):
    """A ``[[acoustics.microphones]]`` entry: its ``name`` (default ``mic<k>``) and position."""

    WHERE: ClassVar[str] = "acoustics.microphones"
    name: Text | None = pydantic.Field(None, json_schema_extra={"default": "mic0, mic1, ... (its index)"})
    position_mm: number_list("[-1e+06, 1e+06]", length=3)


class AcousticsSection(Section):
    """``[acoustics]`` as the file gives it (keys and ranges: the module docstring), checked
    whole; :meth:`inputs` its SI inputs."""

    WHERE: ClassVar[str] = WHERE
    method: Literal["bem", "rayleigh", "erp-only"] = "bem"
    band_Hz: number_list("(0, 1e+05]", length=2) | None = None
    frequencies: number("[1, 2000]", integer=True) = 24
    rank: number("[1, 1e+06]", integer=True) | None = None
    cache: bool = True
    density_kg_m3: number("(0, 1e+04]") = fa.AIR.density
    sound_speed_m_s: number("(0, 1e+05]") = fa.AIR.sound_speed
    microphones: list[Microphone] = pydantic.Field(default_factory=list)

    @pydantic.model_validator(mode="after")
    def _related(self):
        band = self.band_Hz
        if band is not None and not band[1] > band[0]:
            raise sc.fail(WHERE, "band_Hz", "allowed [min, max] with max > min", band)
        names = self.microphone_names()
        for k, label in enumerate(names):
            if label in names[:k]:
                raise sc.fail(f"{WHERE}.microphones[{k}]", "name",
                              "allowed a name no other microphone has", label)
        if names and self.method == "erp-only":
            raise sc.fail(WHERE, "microphones", "not with method = 'erp-only' (no pressure "
                          "field)", names)
        return self

    def microphone_names(self) -> list[str]:
        """Each microphone's name (``mic<k>`` where the file gives none)."""
        return [f"mic{k}" if m.name is None else m.name for k, m in enumerate(self.microphones)]

    def inputs(self, progress: bool = False) -> AcousticsInputs:
        """The SI inputs (:class:`AcousticsInputs`); ``progress``: the BEM's bars over each
        solve's operator assemblies."""
        name = self.method
        method = fa.BEM(progress=progress) if name == "bem" else ACOUSTICS_METHODS[name]()
        mics = tuple((label, tuple(x * 1e-3 for x in m.position_mm))
                     for label, m in zip(self.microphone_names(), self.microphones, strict=True))
        return AcousticsInputs(
            method=method,
            band=None if self.band_Hz is None else tuple(self.band_Hz),
            frequencies=self.frequencies,
            rank=self.rank,
            cache=self.cache,
            fluid=fa.Fluid(self.density_kg_m3, self.sound_speed_m_s),
            microphones=mics,
        )


#: the keys of ``[acoustics]``
ACOUSTICS_KEYS = set(AcousticsSection.model_fields)


def parse_acoustics(table: dict, progress: bool = False) -> AcousticsInputs:
    """``[acoustics]`` (module docstring) as :class:`AcousticsInputs`
    (:class:`AcousticsSection`); ``progress``: the BEM's bars over each solve's operator
    assemblies.

    Raises:
        SchemaError: an unknown key, a value out of range, a band whose maximum is not above
            its minimum, an unknown method, microphones with ``erp-only``, two microphones of
            one name; one line naming the key, its value and the allowed range.
    """
    return AcousticsSection.read(table).inputs(progress)


def check_band(section: AcousticsSection, orders_hz: tuple[float, float]) -> None:
    """``[acoustics] band_Hz`` meets the orders' frequencies ``orders_hz`` (lowest, highest Hz
    over the ``[whine]`` speeds, :func:`~jaxgear.io._whine_table.order_frequency_range`, the
    highest no higher than the housing's band limit, cut-off / 1.5, above which no order is
    radiated): a band with no order in it radiates nothing the run computes (every sound power
    would be absent).

    Raises:
        SchemaError: the band below the lowest order or above the highest, one line.
    """
    band = section.band_Hz
    if band is None:
        return
    lo, hi = orders_hz
    if band[1] < lo or band[0] > hi:
        raise sc.fail(WHERE, "band_Hz", f"no order of [whine] in it: the orders radiated lie at "
                      f"{lo:.6g} to {hi:.6g} Hz (over [whine]'s speeds, up to the housing's "
                      "cut-off / 1.5); allowed a band that meets them (or leave band_Hz out: the "
                      "orders' range)", band)


def acoustics_of(case, progress: bool = False) -> AcousticsInputs | None:
    """The ``[acoustics]`` inputs of a case (:class:`AcousticsInputs`, of its
    :attr:`Case.acoustics <jaxgear.io.Case>`), None without the table."""
    section = getattr(case, "acoustics", None)
    return None if section is None else section.inputs(progress)


def parse_case_acoustics(data: dict) -> AcousticsSection:
    """A case file's ``[acoustics]`` (:class:`AcousticsSection`), and what it radiates from: the
    housing's skin of ``[housing]`` moved by the ``[whine]`` response (``jaxgear run``), a
    closed surface (method ``bem`` or ``erp-only``).

    Raises:
        SchemaError: the table's own errors, no ``[housing]`` or ``[whine]`` beside it, method
            ``rayleigh`` (a flat baffled panel, not a closed housing).
    """
    section = AcousticsSection.read(data["acoustics"])
    for needed in ("housing", "whine"):
        if needed not in data:
            raise sc.fail("", WHERE, f"radiates the housing's vibration: needs [{needed}] "
                          "too (allowed with [housing] and [whine])", f"[{WHERE}]")
    if section.method == "rayleigh":
        raise sc.fail(WHERE, "method", "a housing's closed skin radiates by 'bem' or "
                      "'erp-only' ('rayleigh' is for a flat baffled panel)", "rayleigh")
    return section
