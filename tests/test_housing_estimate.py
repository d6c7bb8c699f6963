"""Sizes before work (docs/fem_prep.md, "Housing sizes"; docs/housing.md, "Sizes before
work"): the structured box mesh's cells and FE DOFs estimated from its 1D grids against the
meshes the mesher builds (scikit-fem's own count of the basis: exact), its peak memory against
the traced peak, the interior modes estimated from the walls as plates against the count of the
LDLᵀ inertia, and every over-large input refused in one line before the work it would start
(the work itself replaced by a function that fails the test if it is reached)."""

import tracemalloc

import numpy as np
import pytest

import fem_prep
import fem_prep.housing._condense as condense_module
import fem_prep.housing._mesh as mesh_module
import jaxgear.io as jio
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    Tet10,
    box_modes_below,
    estimate_box,
    mesh_box,
    mesh_box_gmsh,
    prepare_housing,
)
from fem_prep.housing._condense import fe_dofs
from jaxgear.cli import main
from jaxgear.io import SchemaError
from jaxgear.io._housing_table import _box, _mesh_size

FEET = tuple(Foot((x, x + 0.03), (y, y + 0.03)) for x in (0.0, 0.08) for y in (0.0, 0.22))
BOXES = {
    "plain": HousingBox(0.1, 0.2, 0.15, 0.01),
    "feet": HousingBox(0.11, 0.25, 0.16, 0.01, feet=FEET),
    # bores in two end walls and the top, one wider than the cells across it
    "bores": HousingBox(0.11, 0.25, 0.16, 0.01,
                        bores=(Bore("x-", (0.07, 0.08), 0.025), Bore("x+", (0.17, 0.08), 0.02),
                               Bore("z+", (0.05, 0.12), 0.015)), feet=FEET),
}


def _fail(*args, **kwargs):
    raise AssertionError("the work started: the refusal must come before it")


@pytest.mark.parametrize("name", BOXES)
@pytest.mark.parametrize(("size", "layers"), [(0.04, 1), (0.02, 2), (0.013, 1)])
@pytest.mark.parametrize("element", [Tet10(), Tet4()], ids=["tet10", "tet4"])
def test_estimated_cells_and_dofs_equal_the_meshers(name, size, layers, element):
    box = BOXES[name]
    est = estimate_box(box, size, layers=layers, quadratic=element.name == "tet10")
    mesh = mesh_box(box, size, layers=layers, element=element)
    assert est.cells == mesh.mesh.t.shape[1]
    assert est.dofs == mesh.n_dofs  # scikit-fem's basis counts the nodes itself
    assert fe_dofs(mesh) == mesh.n_dofs  # the condensation's count, without the basis
    # without its bores the count bounds the box's from above
    bound = estimate_box(box, size, layers=layers, quadratic=element.name == "tet10",
                         bores=False)
    assert bound.cells >= est.cells and bound.dofs >= est.dofs
    assert (bound.dofs == est.dofs) == (not box.bores)


@pytest.mark.parametrize("size", [0.04, 0.01])
def test_the_mesher_memory_estimate_bounds_its_traced_peak(size):
    """The traced peak of the structured mesher lies within [1/2, 1] of the estimate (its
    arrays scale with the whole tensor grid: 1.44 x at every size here)."""
    box = BOXES["bores"]
    tracemalloc.start()
    try:
        mesh_box(box, size)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    est = estimate_box(box, size).mesher_bytes
    assert 0.5 * est <= peak <= est


def test_mesh_box_refuses_a_size_this_machine_cannot_hold_before_the_grid(monkeypatch):
    """fem_prep.housing.mesh_box(box, 1e-4) used to ask for 201 GiB: now one ValueError line
    naming size, the estimate and the limit, before any array is built."""
    monkeypatch.setattr(mesh_module, "_structured", _fail)
    with pytest.raises(ValueError, match=r"^mesh_box: size = 0.0001 m: out of range: the "
                       r"structured mesher's .* grid cells .* need about .* GB, allowed <= .* GB "
                       r"\(half this machine's memory\): a larger size$") as err:
        mesh_box(BOXES["bores"], 1e-4)
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match=r"^mesh_box_gmsh: size = 0.0001 m: out of range"):
        mesh_box_gmsh(BOXES["bores"], 1e-4)  # before gmsh is imported (or found missing)


def test_prepare_housing_refuses_a_mesh_too_large_before_the_assembly(monkeypatch):
    monkeypatch.setattr(fem_prep.resources, "memory_bytes", lambda: 2e8)  # a 200 MB machine
    monkeypatch.setattr(condense_module, "assemble_operators", _fail)
    mesh = mesh_box(BOXES["bores"], 0.02)
    with pytest.raises(ValueError, match=rf"^housing: a mesh of {mesh.n_dofs} DOFs: out of "
                       r"range: the assembly and factors .* allowed <= 0.1 GB"):
        prepare_housing(mesh, fem_prep.Material(), 1000.0)


@pytest.fixture(scope="module")
def helical_box():
    """power-helical-housed's box (340 x 240 mm, 12 mm aluminium walls) and material."""
    case = jio.load_case("power-helical-housed")
    box, _ = _box(case.housing, *case._bearing_layout(case.scene))
    return box, fem_prep.Material(*case.housing.material)


@pytest.mark.parametrize("cutoff", [6750.0, 20000.0])
def test_the_modes_are_counted_before_the_eigen_solve_and_near_the_estimate(
        helical_box, cutoff, monkeypatch):
    """A cut-off with more interior modes than MAX_HOUSING_MODES is refused once the LDLᵀ
    inertia has counted them, before the eigen-solve (here the limit lowered to 1, so that
    the refusal gives the count); the plate estimate lies within a factor of 2 of the count
    (11.9 against 12 at the embedded case's 6.75 kHz; 74 against 112 at 20 kHz)."""
    pytest.importorskip("pypardiso")  # the count (without it: the doubling's bound)
    box, material = helical_box
    monkeypatch.setattr(condense_module, "MAX_HOUSING_MODES", 1)
    monkeypatch.setattr(fem_prep.housing._estimate, "MAX_HOUSING_MODES", 1)
    monkeypatch.setattr(condense_module, "condense", _fail)
    with pytest.raises(ValueError, match=rf"^cutoff_hz = {cutoff:g}: out of range: (\d+) "
                       r"interior housing modes below the cut-off \(counted\), allowed <= 1: "
                       "a lower cut-off$") as err:
        prepare_housing(mesh_box(box, 0.04), material, cutoff)
    counted = int(str(err.value).split(": ")[2].split()[0])
    estimated = box_modes_below(box, material, cutoff)
    assert 0.5 <= estimated / counted <= 2.0


def _case(tmp_path, name, old, new, source="power-helical-housed"):
    """The embedded ``source`` with ``old`` replaced by ``new`` (strings, or tuples of them)."""
    text = jio.embedded_case_text(source)
    for o, n in zip(*((old, new) if isinstance(old, tuple) else ((old,), (new,))), strict=True):
        assert o in text
        text = text.replace(o, n)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return str(path)


HMF = "highest_mesh_frequency_Hz = 4500.0"


# below the first mesh frequency: no order of [whine] (order 1 at 100 rad/s: 557 Hz) in the
# band cut-off / 1.5; inside the documented ranges, beyond this machine
REFUSED = {
    "cutoff 10 Hz": (HMF, "cutoff_Hz = 10.0", (
        r"^\[housing\] cutoff_Hz = 10: out of range: its band \(cut-off / 1.5 = 6.667 Hz\) "
        r"lies below every order of \[whine\] \(order 1 of the mesh frequency at 100 rad/s: "
        r"557 Hz\).*allowed cutoff_Hz >= 835.6")),
    "highest mesh frequency 100 Hz": (HMF, "highest_mesh_frequency_Hz = 100.0", (
        r"^\[housing\] highest_mesh_frequency_Hz = 100 \(cut-off 150 Hz\): out of range: "
        r".*allowed highest_mesh_frequency_Hz >= 557")),
    "cutoff 1e6 Hz": (HMF, "cutoff_Hz = 1e6", (
        r"^\[housing\] cutoff_Hz = 1e\+06: out of range: 6727 interior housing modes below "
        r"the cut-off \(estimated from the walls as plates\), allowed <= 1000")),
    # (the named point "side wall" 0.5 mm under the outer face is put on it: at 0.5 mm cells
    # the skin's nodes lie closer than that, and the point's check comes first)
    "mesh 0.5 mm": (("mesh_size_mm = 40.0", '"side wall" = [236.0'),
                    ("mesh_size_mm = 0.5", '"side wall" = [236.5'), (
        r"^\[housing\] mesh_size_mm = 0.5: out of range: the mesh's 6.01e\+07 grid cells "
        r"need about .* GB, allowed <= .* GB \(half this machine's memory\): a larger "
        r"mesh_size_mm$")),
}


@pytest.mark.parametrize(("old", "new", "message"), REFUSED.values(), ids=REFUSED)
def test_a_housing_beyond_the_machine_is_refused_at_load(tmp_path, monkeypatch, old, new,
                                                         message):
    monkeypatch.setattr(fem_prep.resources, "memory_bytes", lambda: 64e9)  # a 64 GB machine
    for name in ("mesh_box", "condensed_housing"):
        monkeypatch.setattr(fem_prep.housing, name, _fail)
    with pytest.raises(SchemaError, match=message) as err:
        jio.load_case(_case(tmp_path, "case", old, new))
    assert "\n" not in str(err.value)


def test_the_cli_refuses_a_cutoff_below_the_whine_in_one_line_before_any_output(
        tmp_path, capsys):
    path = _case(tmp_path, "cut10", HMF, "cutoff_Hz = 10.0")
    assert main(["run", path, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("jaxgear: error: [housing] cutoff_Hz = 10: out of range")
    assert not (tmp_path / "out").exists()


def test_the_embedded_housings_estimates_equal_their_meshes():
    """The load-time estimate of each embedded box (jaxgear run prints it) against its mesh."""
    for name in ("power-helical-housed", "nrel-5mw-stage3-housed", "nrel-5mw-planetary-housed"):
        case = jio.load_case(name)
        size = case.housing_size()
        layout = ((), [[np.zeros(3)]]) if case.scene is None else \
            case._bearing_layout(case.scene)
        box, _ = _box(case.housing, *layout)
        element = Tet10() if case.housing.element == "tet10" else Tet4()
        mesh = mesh_box(box, _mesh_size(case.housing, box), layers=case.housing.layers,
                        element=element)
        assert (size.cells, size.dofs) == (mesh.mesh.t.shape[1], mesh.n_dofs), name
        assert size.line().startswith(f"housing: about {size.cells} cells, {size.dofs} DOFs")


def test_the_condensation_estimates_against_the_benchmarks_measurements():
    """The memory and CPU time estimated for each housing of the condensation benchmark
    (docs/bench/housing_condensation.json: 39 k to 296 k DOFs, 26 to 38 modes, its peak
    resident memory and CPU seconds) within 20 % (the time's rate is the largest one's, so the
    others test its growth with the DOFs)."""
    import json
    import pathlib

    from fem_prep.housing import condensation_bytes, condensation_seconds

    bench = pathlib.Path(__file__).parents[1] / "docs" / "bench" / "housing_condensation.json"
    for row in json.loads(bench.read_text())["sizes"]:
        n, k, seats = row["dofs"], row["modes_found"], row["seat_dofs"] // 6
        assert condensation_bytes(n, k, seats) == pytest.approx(row["peak_rss_gib"] * 2**30,
                                                                rel=0.2)
        assert condensation_seconds(n, k) == pytest.approx(row["total_cpu_s"], rel=0.2)
