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

from typing import NamedTuple

from fem_prep import acoustics as fa, schema as sc

__all__ = ["ACOUSTICS_KEYS", "ACOUSTICS_METHODS", "AcousticsInputs", "acoustics_of",
           "check_band", "parse_acoustics", "parse_case_acoustics"]

WHERE = "acoustics"
#: ``[acoustics] method`` names
ACOUSTICS_METHODS = {"bem": fa.BEM, "rayleigh": fa.Rayleigh, "erp-only": fa.ERP}
ACOUSTICS_KEYS = {
    "method",
    "band_Hz",
    "frequencies",
    "rank",
    "cache",
    "density_kg_m3",
    "sound_speed_m_s",
    "microphones",
}
_MIC_KEYS = {"name", "position_mm"}


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


def parse_acoustics(table: dict, progress: bool = False) -> AcousticsInputs:
    """``[acoustics]`` (module docstring) as :class:`AcousticsInputs`; ``progress``: the BEM's
    bars over each solve's operator assemblies.

    Raises:
        SchemaError: an unknown key, a value out of range, a band whose maximum is not above
            its minimum, an unknown method, microphones with ``erp-only``, two microphones of
            one name; one line naming the key, its value and the allowed range.
    """
    if not isinstance(table, dict):
        raise sc.fail("", WHERE, "must be a table ([acoustics])", table)
    sc.check_keys(table, ACOUSTICS_KEYS, WHERE)
    name = sc.choice(table, "method", WHERE, tuple(ACOUSTICS_METHODS), "bem")
    band = sc.number_list(table, "band_Hz", WHERE, None, length=2, allowed="(0, 1e+05]")
    if band is not None and not band[1] > band[0]:
        raise sc.fail(WHERE, "band_Hz", "allowed [min, max] with max > min", band)
    n = int(sc.number(table, "frequencies", WHERE, 24, allowed="[1, 2000]", integer=True))
    rank = sc.number(table, "rank", WHERE, None, allowed="[1, 1e+06]", integer=True)
    cache = sc.boolean(table, "cache", WHERE, True)
    rho = sc.number(table, "density_kg_m3", WHERE, fa.AIR.density, allowed="(0, 1e+04]")
    c = sc.number(table, "sound_speed_m_s", WHERE, fa.AIR.sound_speed, allowed="(0, 1e+05]")
    mics = []
    for k, m in enumerate(sc.table_array(table, "microphones", WHERE, _MIC_KEYS)):
        where = f"acoustics.microphones[{k}]"
        label = sc.string(m, "name", where, f"mic{k}")
        xyz = sc.number_list(m, "position_mm", where, length=3, allowed="[-1e+06, 1e+06]")
        if label in [x for x, _ in mics]:
            raise sc.fail(where, "name", "allowed a name no other microphone has", label)
        mics.append((label, tuple(x * 1e-3 for x in xyz)))
    if mics and name == "erp-only":
        raise sc.fail(WHERE, "microphones", "not with method = 'erp-only' (no pressure field)",
                      [x for x, _ in mics])
    method = fa.BEM(progress=progress) if name == "bem" else ACOUSTICS_METHODS[name]()
    return AcousticsInputs(
        method=method,
        band=None if band is None else (band[0], band[1]),
        frequencies=n,
        rank=None if rank is None else int(rank),
        cache=bool(cache),
        fluid=fa.Fluid(rho, c),
        microphones=tuple(mics),
    )


def check_band(table: dict, orders_hz: tuple[float, float]) -> None:
    """``[acoustics] band_Hz`` meets the orders' frequencies ``orders_hz`` (lowest, highest Hz
    over the ``[whine]`` speeds, :func:`~jaxgear.io._whine_table.order_frequency_range`, the
    highest no higher than the housing's band limit, cut-off / 1.5, above which no order is
    radiated): a band with no order in it radiates nothing the run computes (every sound power
    would be absent).

    Raises:
        SchemaError: the band below the lowest order or above the highest, one line.
    """
    band = table.get("band_Hz")
    if band is None:
        return
    lo, hi = orders_hz
    if band[1] < lo or band[0] > hi:
        raise sc.fail(WHERE, "band_Hz", f"no order of [whine] in it: the orders radiated lie at "
                      f"{lo:.6g} to {hi:.6g} Hz (over [whine]'s speeds, up to the housing's "
                      "cut-off / 1.5); allowed a band that meets them (or leave band_Hz out: the "
                      "orders' range)", band)


def acoustics_of(case, progress: bool = False) -> AcousticsInputs | None:
    """The ``[acoustics]`` inputs of a case (:class:`AcousticsInputs`), None without the
    table."""
    raw = getattr(case, "raw", None) or {}
    if "acoustics" not in raw:
        return None
    return parse_acoustics(raw["acoustics"], progress)


def parse_case_acoustics(data: dict) -> AcousticsInputs:
    """A case file's ``[acoustics]``: :func:`parse_acoustics`, and what it radiates from: the
    housing's skin of ``[housing]`` moved by the ``[whine]`` response (``jaxgear run``), a
    closed surface (method ``bem`` or ``erp-only``).

    Raises:
        SchemaError: the table's own errors, no ``[housing]`` or ``[whine]`` beside it, method
            ``rayleigh`` (a flat baffled panel, not a closed housing).
    """
    inputs = parse_acoustics(data["acoustics"])
    for needed in ("housing", "whine"):
        if needed not in data:
            raise sc.fail("", WHERE, f"radiates the housing's vibration: needs [{needed}] "
                          "too (allowed with [housing] and [whine])", f"[{WHERE}]")
    if data["acoustics"].get("method") == "rayleigh":
        raise sc.fail(WHERE, "method", "a housing's closed skin radiates by 'bem' or "
                      "'erp-only' ('rayleigh' is for a flat baffled panel)", "rayleigh")
    return inputs
