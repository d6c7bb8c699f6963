"""Names that left the top-level package for a subpackage still resolve there for one release:
``jaxgear.X`` gives the subpackage's object with a ``DeprecationWarning`` that names the new
home; nothing else about the top level changes (``dir(jaxgear)`` does not list them, an unknown
name is still an ``AttributeError``)."""

from __future__ import annotations

import importlib
import re
import warnings

import pytest

import jaxgear as jg

# The names the top level exported before the rating and planetary packages (and the case
# readers) moved out, by their new home: written from the package's history, not read from it.
MOVED = {
    "rating": (
        "AbstractEdition AbstractRootSection AbstractTreatment Edition2006 Edition2019 "
        "FACTOR_CLAUSES GivenRootSection LoadFactors RootStressMap ShaperCutterSection "
        "SubstituteRack ToothFormFactors face_load_factor factor_clause load_factors member_form "
        "root_stress_map section_factors tooth_form_factors transverse_factor_limits "
        "transverse_load_factor"
    ),
    "planetary": (
        "AbstractPlanetaryMeshes AbstractRingModel CondensedRing CraigBamptonRing "
        "DeviationMeshes Eccentricities ModeType PlanetFlanks PlanetaryDeviations PlanetaryTeeth "
        "RigidRing Unbalances campbell check_assembly classify_modes mesh_phases phasing_excites "
        "planetary_hunting_periods planetary_mesh_stiffness ring_contact_angles ring_excitation "
        "ring_resonances sun_ring_offset"
    ),
    "io": "Case TrainCase contact_law_from_name",
}
# The names the top level re-exported from its subpackages until the top level became the pair's
# model alone (each subpackage's names reached in the subpackage): written from the package's
# history, by their home.
REEXPORTED = {
    "scenes": "Grounded RigidMesh Scene TorsionalPair grounded",
    "planetary": (
        "AbstractPlanetaryModel Central ConstantMeshes ContactMeshes LoadSharing PlanarPlanetary "
        "PlanetaryMember PlanetaryModes PlanetaryQuasiStatic PlanetaryStage SpatialPlanetary "
        "TorsionalPlanetary load_sharing planetary_modes planetary_quasi_static speed_ratio"
    ),
    "gearbox": "GearboxModes GearboxTorsional PairGearboxStage PlanetaryGearboxStage gearbox_modes",
    "rating": (
        "BendingRating CaseHardened GearAccuracy GivenFactors InternalRatingGeometry Lubrication "
        "Nitrided OperatingPoint PairTreatment PittingRating Rating RatingGeometry RatingMaterial "
        "RatingSettings ThroughHardened ToothLoading bending_rating pitting_rating rate"
    ),
}
for _home, _names in REEXPORTED.items():
    MOVED[_home] = f"{MOVED.get(_home, '')} {_names}".strip()
CASES = [(home, name) for home, names in MOVED.items() for name in names.split()]


@pytest.mark.parametrize("home,name", CASES, ids=[n for _, n in CASES])
def test_moved_name_warns_and_resolves(home, name):
    new = getattr(importlib.import_module(f"jaxgear.{home}"), name)
    with pytest.warns(DeprecationWarning, match=re.escape(f"jaxgear.{home}.{name}")) as rec:
        old = getattr(jg, name)
    assert old is new
    assert len(rec) == 1
    assert rec[0].filename == __file__  # attributed to the caller's line (stacklevel)
    assert name not in dir(jg)


# Names the top level re-exported whose home then renamed them: old name -> (home, new name)
RENAMED = {"AbstractGearboxStage": ("dynamics", "AbstractStage")}


@pytest.mark.parametrize("old_home", ["", ".gearbox"])
@pytest.mark.parametrize("name", RENAMED)
def test_renamed_name_warns_and_resolves(name, old_home):
    """The gearbox's stage contract became the engine's (``jaxgear.dynamics.AbstractStage``):
    its old name, at the top level and in ``jaxgear.gearbox``, gives it with one warning that
    names the new home, attributed to the caller's line."""
    home, new_name = RENAMED[name]
    new = getattr(importlib.import_module(f"jaxgear.{home}"), new_name)
    module = importlib.import_module(f"jaxgear{old_home}")
    with pytest.warns(DeprecationWarning, match=re.escape(f"jaxgear.{home}.{new_name}")) as rec:
        old = getattr(module, name)
    assert old is new
    assert len(rec) == 1
    assert rec[0].filename == __file__
    assert name not in dir(module)


def test_from_import_of_a_moved_name():
    with pytest.warns(DeprecationWarning, match=r"jaxgear\.planetary\.campbell"):
        from jaxgear import campbell
    assert campbell is importlib.import_module("jaxgear.planetary").campbell


def test_current_names_do_not_warn_and_unknown_names_fail():
    """The pair's model stays at the top level without a warning, and the subpackages are
    attributes of it after ``import jaxgear`` alone (``jg.rating.rate``, ``jg.planetary.X``)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in ("GearPair", "Modifications", "quasi_static", "MeshModel", "ISO6336"):
            assert callable(getattr(jg, name))
        for home in ("scenes", "dynamics", "planetary", "gearbox", "rating"):
            assert getattr(jg, home) is importlib.import_module(f"jaxgear.{home}")
        assert jg.rating.rate is importlib.import_module("jaxgear.rating").rate
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        jg.no_such_name  # noqa: B018
