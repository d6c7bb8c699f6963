"""A case's one-line description (its teeth, module, torque, stiffness model and scene), as
:mod:`jaxgear.cli.cases` lists it: computed from the loaded case (the model), checked against the
listing's stored lines by the tests)."""

from __future__ import annotations

import functools

from ..io import Case, GearboxForm, PairForm, PlanetaryForm, TrainForm
from ._case_kinds import gear_glossary

__all__ = ["case_line", "form_line"]


def case_line(case: Case) -> str:
    """What ``jaxgear cases`` prints after a case's name: its teeth, module, torque, stiffness
    model and scene, as its file wrote its gears (:attr:`~jaxgear.io.Case.form`: a pair's, a
    train's)."""
    return form_line(case.form, case)


@functools.singledispatch
def form_line(form, case: Case) -> str:
    """:func:`case_line` for a case of ``form`` (:class:`~jaxgear.io.CaseForm`)."""
    raise TypeError(f"jaxgear cases: no line for a case of form {type(form).__name__}")


@form_line.register
def _(form: PairForm, case: Case) -> str:
    scene = case.scene
    return (
        f"z {case.pair.pinion.teeth}/{case.pair.gear.teeth}, "
        f"m_n {case.pair.normal_module * 1e3:g} mm, "
        f"β {case.raw['pair'].get('helix_angle_deg', 0)}°, "
        f"T {case.torque:g} N·m, {case.stiffness_model} stiffness"
        + (f", {scene.model} scene" if scene is not None else "")
        + (" with condensed bodies" if scene is not None and scene.hybrid else "")
        + (" on a flexible housing" if case.housing is not None else "")
    )


@form_line.register
def _(form: TrainForm, case: Case) -> str:
    teeth = "/".join(str(m.teeth) for m in case.members())  # its gears' teeth, input first
    modules = dict.fromkeys(f"{p.normal_module * 1e3:g}" for p in case.pairs)
    glossary = gear_glossary(case.gear_names)
    return (
        f"train z {teeth}, m_n {'/'.join(modules)} mm, "
        f"T {case.torque:g} N·m (input), {case.stiffness_model} stiffness"
        + (f", {case.scene.model} scene" if case.scene is not None else "")
        + (" on a flexible housing" if case.housing is not None else "")
        + (f" ({glossary})" if glossary else "")
    )


@form_line.register
def _(form: PlanetaryForm, case: Case) -> str:
    z_s, z_p, z_r = form.spec.teeth
    teeth = f"{z_s}/{z_p}/-{z_r}" if z_p is not None else f"sun {z_s}, ring {z_r} (lumped)"
    return (
        f"planetary z {teeth}, {form.spec.n_planets} planets, {form.spec.fixed.name.lower()} "
        f"fixed, {form.spec.input.name.lower()} → {form.spec.output.name.lower()}, "
        f"T {case.torque:g} N·m (input)"
        + (" on a flexible housing" if case.housing is not None else "")
    )


@form_line.register
def _(form: GearboxForm, case: Case) -> str:
    stages = ", ".join(s.case.name for s in form.stages)
    return f"gearbox of {len(form.stages)} stages ({stages}), ratio 1:{1 / form.ratio():.6g}"
