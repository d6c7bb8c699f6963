"""fem_prep's disk cache of plane FE tables: the fillet influence tables of
``fem_prep.cached_fillet_influence`` (what ``jaxgear run`` with ``[rating]`` maps root stresses
with) and the tooth compliance tables of ``fem_prep.tooth_compliance``, one mechanism.

References: a table solved afresh (``fem_prep.fillet_influence``, ``use_cache=False``): what
comes from the cache equals it bit for bit, whatever the cache held before (nothing, a whole
entry, a damaged or stale one, the files of two processes racing). Each input of a fillet table,
changed alone, misses the cache and gives a table of its own.
"""

import dataclasses
import json
import math
import os
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

import fem_prep

ROOT = Path(__file__).resolve().parents[1]
MN = 1e-3
TOOTH = fem_prep.ToothGeometry(20, MN, math.radians(20))  # r_F 9.40 mm, r_a 11.0 mm
RADII = np.array([9.95, 10.35, 10.75]) * 1e-3  # on the involute of every variant below
SIZE = MN / 6  # coarse: 0.3 s a table on a 2-core machine
LOOKUP = ("cache_hit", "key")  # FilletInfluence fields that describe the lookup, not the table


def _fillet_dir(root) -> Path:
    return Path(root) / "fillet_influence"


def _assert_same_table(got, want):
    """Every field of the table identical: arrays bit for bit (values and dtypes)."""
    for f in dataclasses.fields(want):
        if f.name in LOOKUP:
            continue
        a, b = getattr(got, f.name), getattr(want, f.name)
        if isinstance(b, np.ndarray):
            assert a.dtype == b.dtype and a.shape == b.shape, f.name
            assert a.tobytes() == b.tobytes(), f.name
        else:
            assert a == b and type(a) is type(b), f.name


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


@pytest.fixture(scope="module")
def fresh():
    """The base table solved without the cache (the reference)."""
    return fem_prep.fillet_influence(TOOTH, RADII, size=SIZE)


def test_cached_table_is_the_fresh_solve_bit_for_bit(cache, fresh):
    first = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert not first.cache_hit and len(first.key) == 32
    assert [p.name for p in _fillet_dir(cache).iterdir()] == [f"{first.key}.npz"]
    _assert_same_table(first, fresh)
    # read back (the radii in another order are the same table: it sorts them)
    again = fem_prep.cached_fillet_influence(TOOTH, RADII[::-1], size=SIZE)
    assert again.cache_hit and again.key == first.key
    _assert_same_table(again, fresh)


def test_tooth_compliance_table_from_the_shared_cache_is_bit_identical(cache):
    args = {"size": MN / 2, "model": fem_prep.SectorModel(n_teeth=3, n_roll=6)}
    want = fem_prep.tooth_compliance(TOOTH, use_cache=False, **args)
    first = fem_prep.tooth_compliance(TOOTH, **args)
    again = fem_prep.tooth_compliance(TOOTH, **args)
    assert not first.cache_hit and again.cache_hit and again.key == first.key
    assert [p.name for p in (cache / "tooth_fe").iterdir()] == [f"{first.key}.npz"]
    for name in ("roll", "load_radius", "compliance", "compliance_tooth"):
        assert getattr(again, name).tobytes() == getattr(want, name).tobytes(), name


# each input of the fillet table, changed alone (the radii stay on every variant's involute)
CHANGES = {
    "teeth": {"geometry": dataclasses.replace(TOOTH, teeth=21)},
    "normal_module": {"geometry": dataclasses.replace(TOOTH, normal_module=1.05e-3)},
    "pressure_angle": {"geometry": dataclasses.replace(TOOTH, normal_pressure_angle=0.384)},
    "helix_angle": {"geometry": dataclasses.replace(TOOTH, helix_angle=math.radians(10))},
    "profile_shift": {"geometry": dataclasses.replace(TOOTH, profile_shift=0.2)},
    "addendum_coeff": {"geometry": dataclasses.replace(TOOTH, addendum_coeff=0.9)},
    "dedendum_coeff": {"geometry": dataclasses.replace(TOOTH, dedendum_coeff=1.2)},
    "fillet_radius_coeff": {"geometry": dataclasses.replace(TOOTH, fillet_radius_coeff=0.35)},
    "load_radii": {"load_radii": RADII + np.array([0.0, 0.0, 1e-6])},
    "one_radius_less": {"load_radii": RADII[:2]},
    "size": {"size": MN / 5},
    "rim_radius": {"rim_radius": 6.5e-3},
    "n_teeth": {"n_teeth": 3},
    "poisson_ratio": {"poisson_ratio": 0.25},
    "form": {"form": fem_prep.CircularFillet()},
    "section": {"section": fem_prep.NormalSection()},
    "support_ring_segment": {"support": fem_prep.RingSegment(3)},
    "support_webbed_rim": {"support": fem_prep.WebbedRim()},
    "webbed_rim_web": {"support": fem_prep.WebbedRim(web=0.5)},
}


@pytest.fixture(scope="module")
def shared(tmp_path_factory, fresh):
    """A cache holding the base table (written once for the module)."""
    root = tmp_path_factory.mktemp("fe_cache_shared")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("FEM_PREP_CACHE", str(root))
        base = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert not base.cache_hit
    return root, base


@pytest.mark.parametrize("change", sorted(CHANGES))
def test_each_input_misses_the_cache(change, shared, fresh, monkeypatch):
    root, base = shared
    monkeypatch.setenv("FEM_PREP_CACHE", str(root))
    args = {"geometry": TOOTH, "load_radii": RADII, "size": SIZE, **CHANGES[change]}
    geometry, radii = args.pop("geometry"), args.pop("load_radii")
    got = fem_prep.cached_fillet_influence(geometry, radii, **args)
    assert not got.cache_hit and got.key != base.key
    assert (_fillet_dir(root) / f"{got.key}.npz").is_file()
    # the input changes the table (a spur gear's normal section is its transverse one: the
    # stresses are the same, the table names its section)
    differs = [
        f.name
        for f in dataclasses.fields(fresh)
        if f.name not in LOOKUP and not np.array_equal(getattr(got, f.name), getattr(fresh, f.name))
    ]
    assert differs
    # and the base entry is still the base table
    again = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert again.cache_hit and again.key == base.key
    _assert_same_table(again, fresh)


def _rewrite(path: Path, edit) -> None:
    """Load an entry's arrays, ``edit`` the dict, write it back (a valid zip again)."""
    with np.load(path) as z:
        data = {k: z[k] for k in z.files}
    edit(data)
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _flip_a_number(path: Path) -> None:
    """Flip one byte of the last number of the table's main array, in place (np.savez stores
    its members uncompressed, each with a CRC-32)."""
    main = {"fillet_influence": "array_sigma_t.npy", "tooth_fe": "compliance_E.npy"}
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo(main[path.parent.name])
    raw = bytearray(path.read_bytes())
    h = info.header_offset  # local header: 30 bytes, then the name and the extra field
    start = h + 30 + int.from_bytes(raw[h + 26 : h + 28], "little")
    start += int.from_bytes(raw[h + 28 : h + 30], "little")
    raw[start + info.compress_size - 2] ^= 0x10  # a bit of the last float's exponent
    path.write_bytes(bytes(raw))


DAMAGE = {
    "truncated": lambda p: p.write_bytes(p.read_bytes()[: p.stat().st_size // 2]),
    "empty": lambda p: p.write_bytes(b""),
    "not_a_zip": lambda p: p.write_bytes(b"not an npz file\n" * 64),
    "flipped_bit": _flip_a_number,
    "other_format_version": lambda p: _rewrite(
        p, lambda d: d.update(format_version=d["format_version"] + 1)
    ),
    "other_key": lambda p: _rewrite(p, lambda d: d.update(key=np.array("0" * 32))),
    "other_inputs": lambda p: _rewrite(
        p,
        lambda d: d.update(
            inputs=np.array(json.dumps({**json.loads(str(d["inputs"])), "poisson_ratio": 0.2}))
        ),
    ),
    "missing_array": lambda p: _rewrite(p, lambda d: d.pop("array_sigma_t")),
}


@pytest.fixture(scope="module")
def entry(shared):
    """The base entry's bytes (a whole file, to damage)."""
    root, base = shared
    return base.key, (_fillet_dir(root) / f"{base.key}.npz").read_bytes()


@pytest.mark.parametrize("damage", sorted(DAMAGE))
def test_damaged_or_stale_entry_is_solved_again_and_replaced(damage, cache, entry, fresh):
    key, raw = entry
    path = _fillet_dir(cache) / f"{key}.npz"
    path.parent.mkdir(parents=True)
    path.write_bytes(raw)
    DAMAGE[damage](path)
    assert path.read_bytes() != raw
    got = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert not got.cache_hit and got.key == key  # not trusted: solved again
    _assert_same_table(got, fresh)
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # replaced, no temporary left
    again = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert again.cache_hit
    _assert_same_table(again, fresh)


@pytest.mark.parametrize("damage", ["flipped_bit", "other_format_version", "other_inputs"])
def test_damaged_tooth_compliance_entry_is_solved_again(damage, cache):
    args = {"size": MN / 2, "model": fem_prep.SectorModel(n_teeth=3, n_roll=6)}
    first = fem_prep.tooth_compliance(TOOTH, **args)
    path = cache / "tooth_fe" / f"{first.key}.npz"
    DAMAGE[damage](path)
    got = fem_prep.tooth_compliance(TOOTH, **args)
    assert not got.cache_hit
    assert got.compliance.tobytes() == first.compliance.tobytes()
    assert fem_prep.tooth_compliance(TOOTH, **args).cache_hit


def test_unwritable_cache_warns_and_returns_the_table(tmp_path, monkeypatch, fresh):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    monkeypatch.setenv("FEM_PREP_CACHE", str(blocker / "cache"))  # under a file: no folder
    with pytest.warns(UserWarning, match="fem_prep cache: .* not written"):
        got = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert not got.cache_hit
    _assert_same_table(got, fresh)


# Two processes solve the same table and write it at the same moment: numpy.savez (what the
# cache writes an entry with) waits in each until both are inside it, so both temporary files
# exist at once and both are renamed onto the one path.
RACER = textwrap.dedent(
    """
    import math, sys, time
    from pathlib import Path
    import numpy as np
    import fem_prep

    me, folder = sys.argv[1], Path(sys.argv[2])
    real_savez = np.savez

    def savez(fh, **data):
        (folder / f"in-savez-{me}").touch()
        t0 = time.monotonic()
        while len(list(folder.glob("in-savez-*"))) < 2:
            if time.monotonic() - t0 > 120:
                raise SystemExit("the other process never came to write")
            time.sleep(0.01)
        real_savez(fh, **data)

    np.savez = savez
    tooth = fem_prep.ToothGeometry(20, 1e-3, math.radians(20))
    radii = np.array([9.95, 10.35, 10.75]) * 1e-3
    t = fem_prep.cached_fillet_influence(tooth, radii, size=1e-3 / 6)
    print(int(t.cache_hit), t.key, t.sigma_t.tobytes().hex()[:64])
    """
)


# default tier: tests/test_fe_cache.py::test_cli_fillet_table_reads_the_disk_cache_in_a_new_process (an entry written whole and read back) and test_damaged_or_stale_entry_is_solved_again_and_replaced (a torn entry is solved again)
@pytest.mark.slow  # an environment property run in subprocesses (two racing writers)
def test_two_processes_writing_the_same_entry_leave_one_whole_file(cache, tmp_path, fresh):
    sync = tmp_path / "sync"
    sync.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}  # FEM_PREP_CACHE: the fixture's
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", RACER, str(i), str(sync)],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(2)
    ]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-2000:] for o in outs]
    lines = [o[0].split() for o in outs]
    assert [line[0] for line in lines] == ["0", "0"]  # both solved it and wrote it
    assert lines[0][1:] == lines[1][1:]
    key = lines[0][1]
    assert [p.name for p in _fillet_dir(cache).iterdir()] == [f"{key}.npz"]  # no temporary
    got = fem_prep.cached_fillet_influence(TOOTH, RADII, size=SIZE)
    assert got.cache_hit and got.key == key
    _assert_same_table(got, fresh)


def test_cli_fillet_table_reads_the_disk_cache_in_a_new_process(cache):
    """``jaxgear.cli.fillet_table`` (what ``jaxgear run`` maps root stresses with): a second
    process (here: the in-process cache cleared) reads the table the first one wrote."""
    from jaxgear import cli

    radii = tuple(float(r) for r in RADII)
    cli.fillet_table.cache_clear()
    first = cli.fillet_table(TOOTH, radii)
    cli.fillet_table.cache_clear()
    again = cli.fillet_table(TOOTH, radii)
    cli.fillet_table.cache_clear()
    assert not first.cache_hit and again.cache_hit and again.key == first.key
    assert first.section == "normal" and len(list(_fillet_dir(cache).glob("*.npz"))) == 1
    _assert_same_table(again, first)  # the first: fillet_influence's own solve
