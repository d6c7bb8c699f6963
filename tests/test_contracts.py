"""What a kind supports is declared on its contract, never probed.

The model code (``jaxgear/`` less the edge, ``cli/`` and ``io/``) asks no object whether it
has an attribute: no ``hasattr(x, "name")`` and no ``getattr(x, "name", default)``. What a
kind of model, scene, member or result supports is stated on its contract (a ClassVar, a
method of the abstract class whose default refuses in one line, an ``isinstance`` against the
contract class, or a type that always has the field), so that a kind that lacks it is refused
before any work, in one line, instead of falling through a probe. A static scan of the source
checks the rule (with an allow-list of one line of reason per entry; an entry that no longer
matches fails too), and the dynamic-model kinds are checked to implement what they declare.
"""

from __future__ import annotations

import ast
import inspect
import pathlib

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg  # every model kind imported
import jaxgear.dynamics as jd
import jaxgear.gearbox  # noqa: F401
import jaxgear.planetary

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: the edge: it names and presents (reads files, writes outputs), where a look at what a file or
#: a summary holds is its job; the scan covers the rest of the package
EDGE = ("cli", "io")

#: probes the rule allows, "path: call as ast.unparse writes it" -> why it is not a probe of what
#: a kind supports. Empty: every former probe is now a declaration on a contract.
ALLOWED: dict[str, str] = {}


def probes(source: str) -> list[tuple[int, str]]:
    """(line, call) of each ``hasattr(...)`` and three-argument ``getattr(obj, name,
    default)`` in ``source``. A two-argument ``getattr(obj, name)`` is a field read by name
    (a known list of dataclass fields, a solver's class by its name), not a probe."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
            continue
        if node.func.id == "hasattr" or (node.func.id == "getattr" and len(node.args) == 3):
            out.append((node.lineno, ast.unparse(node)))
    return sorted(out)


def _model_sources():
    for path in sorted((ROOT / "jaxgear").rglob("*.py")):
        rel = path.relative_to(ROOT)
        if rel.parts[1] not in EDGE:
            yield rel, path.read_text()


def test_the_scan_finds_hasattr_and_getattr_defaults_only():
    """The detector on a source written for it: both probes found at their lines, a field read
    by name and an attribute access not."""
    src = (
        "a = hasattr(model, 'whine')\n"
        "b = getattr(model, 'centre', None)\n"
        "c = [getattr(m, name) for name in FIELDS]\n"
        "d = model.whine\n"
        "e = obj.hasattr(x, 'y')\n"
    )
    assert probes(src) == [(1, "hasattr(model, 'whine')"), (2, "getattr(model, 'centre', None)")]


def test_model_code_declares_instead_of_probing():
    """No probe in the model code outside :data:`ALLOWED`; every allowed entry still there."""
    found = {
        f"{rel}: {call}": line for rel, src in _model_sources() for line, call in probes(src)
    }
    new = [f"{key.split(': ', 1)[0]}:{found[key]}: {key.split(': ', 1)[1]}"
           for key in found if key not in ALLOWED]
    assert not new, (
        "probes of what an object supports in model code; declare it on the kind's contract "
        f"(a ClassVar, a method refusing in one line, an isinstance of the contract class): {new}"
    )
    stale = [key for key in ALLOWED if key not in found]
    assert not stale, f"allow-list entries that no longer match the source: {stale}"
    assert all(reason.strip() and "\n" not in reason for reason in ALLOWED.values())


def _kinds():
    """Every concrete dynamic-model kind of the package."""
    seen, todo = [], [jd.AbstractDynamicModel]
    while todo:
        cls = todo.pop()
        for sub in cls.__subclasses__():
            if sub.__module__.startswith("jaxgear") and sub not in seen:
                seen.append(sub)
                todo.append(sub)
    return [k for k in seen if not inspect.isabstract(k)]


def _overrides(kind, name) -> bool:
    return getattr(kind, name) is not getattr(jd.AbstractDynamicModel, name)


@pytest.mark.parametrize("kind", _kinds(), ids=lambda k: k.__name__)
def test_each_kind_implements_what_it_declares(kind):
    """A kind's capability ClassVars and its methods agree: whine methods if and only if its
    own ``whine``; ``settles`` if and only if its own ``settling_measures``, and only a kind
    that continues from speed to speed; ``runs_from_position`` if and only if its own
    ``independent_at``; ``continues`` if and only if its own ``continuation``."""
    assert bool(kind.whine_methods) == _overrides(kind, "whine")
    assert all(issubclass(m, jd.AbstractWhineMethod) for m in kind.whine_methods)
    assert kind.settles == _overrides(kind, "settling_measures")
    assert not kind.settles or kind.continues
    assert kind.runs_from_position == _overrides(kind, "independent_at")
    assert kind.continues == _overrides(kind, "continuation")
    assert kind.band_factor == _overrides(kind, "mesh_force_ratios")


def test_the_kinds_found_are_the_engines():
    names = {k.__name__ for k in _kinds()}
    assert {"DynamicModel", "HybridModel", "PlanetaryModel", "GearboxModel"} <= names


#: one integrator of each kind the engine has (Newmark, a diffrax solver)
INTEGRATORS = (jd.Newmark(), jd.DiffraxIntegrator("tsit5"))


@pytest.mark.parametrize("kind", _kinds(), ids=lambda k: k.__name__)
def test_each_kind_declares_the_integrators_its_model_accepts(kind):
    """A kind's declared integrator types (asked of the class, ``jaxgear sweep --solver`` at
    load) are exactly those its model's ``check_integrator`` lets through (written apart, in
    the kind's own words; it reads the kind only, so a bare instance asks it), and its
    declared contact laws are contact laws; a refusal is one line."""
    model = kind.__new__(kind)
    for integrator in INTEGRATORS:
        try:
            model.check_integrator(integrator)
            accepted = True
        except ValueError as err:
            accepted = False
            assert "\n" not in str(err)
        assert kind.runs(integrator) == accepted, (kind.__name__, type(integrator).__name__)
    assert set(kind.integrators) <= {jd.Newmark, jd.DiffraxIntegrator}
    assert kind.contact_laws and all(issubclass(c, jg.AbstractContactLaw)
                                     for c in kind.contact_laws)


def test_the_declared_integrators_of_the_engines():
    """The lumped model alone takes a diffrax solver (its first-order form); the hybrid, the
    planetary and the gearbox models run Newmark."""
    declared = {k.__name__: k.integrators for k in _kinds()}
    assert declared["DynamicModel"] == (jd.Newmark, jd.DiffraxIntegrator)
    for name in ("HybridModel", "PlanetaryModel", "GearboxModel"):
        assert declared[name] == (jd.Newmark,)


def test_a_gearbox_runs_the_smooth_law_it_declares():
    """The gearbox model declares both contact laws: a coupled run of a two-pair chain (one
    constant cell per mesh) with the smooth law of a small width runs (result 0) and gives
    the exact law's dynamic factors to 1e-3 (the smooth law's offset of order its width)."""
    import jaxgear.gearbox as gb

    chain = gb.GearboxTorsional(
        (gb.PairGearboxStage((0.02, 0.3), (0.04, 0.1), 5e8, input=0),
         gb.PairGearboxStage((0.05, 0.8), (0.05, 0.12), 8e8, input=0)), (2e6,))
    run = gb.GearboxRun(100.0, 1e6, steps_per_period=16, periods=4, keep_periods=2)
    assert jg.SmoothContact in gb.GearboxModel.contact_laws
    smooth = gb.gearbox_dynamics(chain, run, 100.0, jg.SmoothContact(1e-9, 50))
    exact = gb.gearbox_dynamics(chain, run, 100.0, jg.ExactContact())
    assert int(smooth.result) == 0 and int(exact.result) == 0
    np.testing.assert_allclose(np.asarray(smooth.dynamic_factors),
                               np.asarray(exact.dynamic_factors), rtol=1e-3)


class _ExactOnly(jd.DynamicModel):
    """The lumped kind declaring the exact law alone."""

    contact_laws = (jg.ExactContact,)


def test_a_law_a_kind_does_not_declare_is_refused_before_any_work():
    """:func:`jaxgear.dynamics.resolve_settings` (every run's first step) refuses a contact law
    of a type the kind does not declare, in one line, naming the allowed ones."""
    model = _ExactOnly.__new__(_ExactOnly)
    with pytest.raises(ValueError) as err:
        jd.resolve_settings(model, jd.Newmark(64), jg.SmoothContact(1e-7), jd.SteadyState(4, 2))
    assert str(err.value) == ("contact = SmoothContact(...): a _ExactOnly does not run it "
                              "(allowed ExactContact(...))")


class _Bare(jd.AbstractDynamicModel):
    """A kind that declares no optional capability (the abstract methods only)."""

    scene: object = None
    mods: object = None
    torque: jnp.ndarray = eqx.field(default_factory=lambda: jnp.asarray(1.0))

    def default_settings(self):
        raise AssertionError("not reached: the capability is refused first")

    def check_integrator(self, integrator):
        raise AssertionError("not reached")

    def span_periods(self):
        return 1

    def steps_multiple(self):
        return 1

    def averaged_modes(self, **kw):
        raise AssertionError("not reached")

    def prepare(self, *a, **kw):
        raise AssertionError("not reached")

    def independent(self, *a, **kw):
        raise AssertionError("not reached")


@pytest.mark.parametrize(
    "call, error, message",
    [
        (lambda m: jd.whine_response(m, [100.0]), TypeError,
         r"^model: _Bare has no gear whine \(its whine_methods is empty\)$"),
        (lambda m: m.whine([100.0], jd.HarmonicBalance()), TypeError, r"^model: _Bare has no gear"),
        (lambda m: jd.settled_sweep(m, [100.0, 200.0]), ValueError,
         r"^model = _Bare: a settled sweep continues from speed to speed; allowed a kind that "
         r"settles"),
        (lambda m: m.settling_measures(), ValueError, r"^model = _Bare: does not settle"),
        (lambda m: m.independent_at(None, 1.0, 0, None), ValueError,
         r"^model = _Bare: its runs start at mesh position 0"),
        (lambda m: jd.band_dynamic_factor(m, [100.0, 200.0]), ValueError,
         r"^model = _Bare: has no band dynamic factor \(its band_factor is False"),
        (lambda m: m.mesh_force_ratios(None), ValueError,
         r"^model = _Bare: has no band dynamic factor"),
    ],
    ids=["whine_response", "whine", "settled_sweep", "settling_measures", "independent_at",
         "band_dynamic_factor", "mesh_force_ratios"],
)
def test_a_kind_without_a_capability_is_refused_in_one_line(call, error, message):
    """Before any work (the bare kind's run methods are never reached), in one line."""
    with pytest.raises(error, match=message) as err:
        call(_Bare())
    assert "\n" not in str(err.value)


def test_whine_method_refused_by_the_kind_declaration():
    """A method outside a kind's ``whine_methods`` (a hybrid pair's: no torus of several mesh
    frequencies) and an object that is no method, in one line, before any work."""
    hybrid = jd.HybridModel.__new__(jd.HybridModel)  # the check reads the kind only
    with pytest.raises(TypeError, match=r"^method = QuasiPeriodicBalance\(\.\.\.\): not for a "
                       r"HybridModel \(its whine methods: HarmonicBalance\(\.\.\.\), "
                       r"TransmissionErrorSource\(\.\.\.\)\)$"):
        jd.whine_response(hybrid, [100.0], jd.QuasiPeriodicBalance(2))
    with pytest.raises(TypeError, match=r"^method = 'hb': allowed HarmonicBalance"):
        jd.whine_response(hybrid, [100.0], "hb")
    with pytest.raises(TypeError, match=r"^model: str: allowed a "
                       r"jaxgear.dynamics.AbstractDynamicModel"):
        jd.whine_response("model", [100.0])


@pytest.mark.parametrize("kind", [jaxgear.planetary.PlanetaryModel, jaxgear.gearbox.GearboxModel],
                         ids=lambda k: k.__name__)
def test_band_dynamic_factor_refuses_a_kind_without_it(kind):
    """A planetary stage and a gearbox declare no band dynamic factor (their responses are the
    stage's and the gearbox's, not a DynamicResponse): band_dynamic_factor refuses them in one
    line naming the kind and what it lacks, before any work (the check reads the kind only),
    where it raised an AttributeError from inside the sweep's records before."""
    model = kind.__new__(kind)
    assert not kind.band_factor
    with pytest.raises(ValueError, match=rf"^model = {kind.__name__}: has no band dynamic "
                       r"factor \(its band_factor is False: its response does not give each "
                       r"mesh's force over its static force") as err:
        jd.band_dynamic_factor(model, [100.0, 200.0])
    assert "\n" not in str(err.value)
    with pytest.raises(TypeError, match=r"^model: str: allowed a "
                       r"jaxgear.dynamics.AbstractDynamicModel"):
        jd.band_dynamic_factor("model", [100.0])
