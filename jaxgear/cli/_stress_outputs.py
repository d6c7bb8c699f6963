"""The stresses ``jaxgear run`` reports beside the rating: the plane FE tooth's fillet stress per
unit load (:func:`fillet_table`) over the active profile (:func:`active_radii`), and the rim
and web stresses of condensed bodies (:func:`body_stress_outputs`)."""

from __future__ import annotations

import functools
import os

import numpy as np

import fem_prep

from .. import GearPair

__all__ = ["active_radii", "body_stress_outputs", "fillet_table"]


@functools.lru_cache(maxsize=32)
def fillet_table(tooth, radii: tuple) -> fem_prep.FilletInfluence:
    """The FE fillet stress per unit transverse line load at each of ``radii`` (m, on the
    member's transverse flank) of a tooth form (:func:`fem_prep.fillet_influence`) in ISO's
    normal section (:class:`fem_prep.NormalSection`: the virtual spur tooth of a helical gear,
    loaded at the same height; a spur gear's own tooth), cached for the process and on disk
    (:func:`fem_prep.cached_fillet_influence`, under ``$FEM_PREP_CACHE``): one FE factorisation
    per tooth form and radii, ever (a train's gear of two meshes, a later run of the case). An
    internal tooth (:class:`fem_prep.InternalToothGeometry`, its form the one its cutter
    generates) in its transverse section: it has no virtual spur gear yet (a spur ring's
    transverse section is ISO's)."""
    return fem_prep.cached_fillet_influence(
        tooth, np.asarray(radii), section=_iso_section(tooth)
    )


@functools.singledispatch
def _iso_section(tooth) -> fem_prep.RootSection:
    """The section an external tooth's fillet table is computed in: ISO's normal section."""
    return fem_prep.NormalSection()


@_iso_section.register
def _ring_section(tooth: fem_prep.InternalToothGeometry) -> fem_prep.RootSection:
    """An internal tooth's: its transverse section (no virtual spur gear of a ring yet)."""
    return fem_prep.TransverseSection()


def active_radii(pair: GearPair, member: int, n: int) -> tuple:
    """``n`` radii (m) over the member's active profile (roll distances of s = 0 and s = g_α),
    the tip end held at the tip circle (its radius from the roll differs by round-off; an
    internal gear's tip circle is its smallest radius)."""
    ends = [pair.roll_distance(s, member) for s in (0.0, float(pair.path_of_contact))]
    roll = np.linspace(min(ends), max(ends), n)
    radii = np.hypot(roll, float(pair.base_radii[member]))
    tip = float(pair.tip_radii[member])
    internal = member == 1 and pair.gear.teeth < 0
    radii = np.maximum(radii, tip) if internal else np.minimum(radii, tip)
    return tuple(float(r) for r in radii)


#: the body regions whose largest stresses ``body_stress_outputs`` reports, where the body has them
_BODY_REGIONS = ("rim", "web", "hub", "pinion_rim")


def body_stress_outputs(out_dir: str, flexible, x) -> tuple[dict, list[str]]:
    """Rim and web stresses of each condensed body of a hybrid scene's quasi-static solution
    (:func:`fem_prep.condensed_body_stress`: the body's corner field ``recovery @ q``, element
    means, linear hexahedra), one evaluation per body, no JAX.

    ``flexible``: ``(name, member, body)`` of each condensed body (a member's ``body_dofs``
    pick its coordinates out of ``x``); ``x``: the scene's coordinates at one position
    (``res.x[k]``, body frame; the tooth loads and, at speed, the centrifugal load).

    Returns ``({name: {region: {"von_mises_Pa", "hoop_Pa"}}}, files)``: per body the largest
    von Mises stress and the largest-magnitude hoop stress (signed, Pa) over the elements of
    each region it has ("rim", "web", "hub", "pinion_rim"), and the ``body_<name>_stress.vtu``
    files written to ``out_dir`` (cell data von_mises_Pa, hoop_Pa, radial_Pa, axial_Pa, region;
    point data displacement, m; body frame)."""
    out, files = {}, []
    for name, member, body in flexible:
        q = np.asarray(x, dtype=float)[np.asarray(member.body_dofs)]
        u, stress = fem_prep.condensed_body_stress(body, q)
        present = set(np.unique(stress.region).tolist())
        out[name] = {r: stress.max_in(r) for r in _BODY_REGIONS if fem_prep.REGIONS[r] in present}
        fname = f"body_{name}_stress.vtu"
        fem_prep.write_stress_vtu(body, u, stress, os.path.join(out_dir, fname))
        files.append(fname)
    return out, files
