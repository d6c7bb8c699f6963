"""The exact cell-space contact solve on a factored full contact set
(:func:`jaxgear.solve_factored_cells`) against the independent solve that factors every active-set pass
(:func:`jaxgear.solve_contact_cells`), on synthetic problems: every cell in contact, a few
cells out (Schur complement on the dropped cells), most cells out (factorisation of the active
ones), one whole contact line out (its cached inverse), with and without the lines cached;
zero, one and two rigid-body amplitudes; derivatives against central differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
from jaxgear import CellFactor, line_factors, solve_factored_cells

C_CELLS = 14
LINES = np.arange(C_CELLS).reshape(2, C_CELLS // 2)  # two contact lines of 7 cells


def _problem(r: int, seed: int = 0):
    """A cell compliance C (SPD, m/N), k, l, a mask with two cells off the flanks, E (c, r)
    (the rigid approach of the cells: a translation and a tilt) and B = (I + S C S)⁻¹,
    S = diag √(k l) on the mask."""
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(C_CELLS, C_CELLS))
    C = 2e-9 * (X @ X.T / C_CELLS + 0.5 * np.eye(C_CELLS))
    k = rng.uniform(1.0e10, 2.0e10, C_CELLS)
    length = np.full(C_CELLS, 1e-3)
    mask = np.ones(C_CELLS, bool)
    mask[[3, 9]] = False
    lever = np.linspace(-0.5, 0.5, C_CELLS)
    E = np.stack([np.ones(C_CELLS), lever], 1)[:, :r] + 0.01 * rng.uniform(-1, 1, (C_CELLS, r))
    kl = np.where(mask, k * length, 0.0)
    s = np.sqrt(kl)
    B = np.linalg.inv(np.eye(C_CELLS) + s[:, None] * C * s[None, :])
    return C, k, length, mask, E, kl, 0.5 * (B + B.T)


def _gaps(kind: str, r: int):
    """Free gaps a (m) and loads b: all cells in contact, a few out, most out, one line out."""
    z = np.linspace(0.0, 1.0, C_CELLS)
    base = {
        "all": 5e-6 + 1e-8 * z,
        "few": 5e-6 - 8e-6 * z**4,
        "most": -4e-6 + 6e-6 * z**12,
        "line": np.where(np.arange(C_CELLS) < C_CELLS // 2, 5e-6, -3e-6),
    }[kind]
    b = np.array([60.0, 3.0])[:r]  # N and N·(unit lever) on the rigid modes (r = 0: none)
    return base, b


@pytest.mark.parametrize("lines", [False, True])
@pytest.mark.parametrize("r", [0, 1, 2])
@pytest.mark.parametrize("kind", ["all", "few", "most", "line"])
def test_factored_solve_equals_the_per_pass_factorisation(r, kind, lines):
    C, k, length, mask, E, kl, B = _problem(r)
    a, b = _gaps(kind, r)
    ref, p_ref, al_ref = jg.solve_contact_cells(
        jnp.asarray(C), jnp.asarray(a), jnp.asarray(E), jnp.asarray(b), jnp.asarray(k),
        jnp.asarray(length), jnp.asarray(mask), jg.ExactContact(),
    )  # fmt: skip
    extra = (LINES, *line_factors(B, E, kl, mask, LINES)) if lines else (None, None, None)
    sol, p, al = jax.jit(solve_factored_cells, static_argnums=4)(
        CellFactor(B, C, E, kl, mask, *extra), jnp.asarray(a), jnp.asarray(b), jnp.asarray(k), 100
    )
    assert int(ref.result) == 0 and int(sol.result) == 0
    weight = np.asarray(ref.weight)
    n_on, active = int(mask.sum()), int(weight.sum())
    if kind == "all":
        assert active == n_on
    elif kind == "few":
        assert 0 < n_on - active <= (C_CELLS + 1) // 2  # the Schur complement on D
    elif kind == "most":
        assert n_on - active > (C_CELLS + 1) // 2  # the factorisation of A
    elif r < 2:  # the second line whole (its cached inverse when lines are given)
        np.testing.assert_array_equal(weight, mask & (np.arange(C_CELLS) < C_CELLS // 2))
    np.testing.assert_array_equal(np.asarray(sol.weight), weight)
    assert int(sol.iterations) == int(ref.iterations)
    scale = np.abs(np.asarray(p_ref)).max()
    np.testing.assert_allclose(np.asarray(p), np.asarray(p_ref), rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(
        np.asarray(sol.x)[mask], np.asarray(ref.x)[mask], rtol=0, atol=1e-12 * np.abs(a).max()
    )
    if r:
        np.testing.assert_allclose(np.asarray(al), np.asarray(al_ref), rtol=1e-12, atol=0)


# default tier for "most" and "line": the "few" derivative here (the same implicit derivative of
# the factored solve) and test_factored_solve_equals_the_per_pass_factorisation (their branches)
@pytest.mark.parametrize(
    "kind", ["few", pytest.param("most", marks=pytest.mark.slow),
             pytest.param("line", marks=pytest.mark.slow)]
)
def test_factored_solve_derivatives_equal_central_differences(kind):
    """d(Σ P_c² + α²)/d(gap shift) and d/d(load), forward and reverse, against central
    differences (the active set does not change within the step)."""
    C, k, _, mask, E, kl, B = _problem(1, seed=3)
    a0, b0 = _gaps(kind, 1)
    tilt = np.linspace(-1.0, 1.0, C_CELLS)
    K_line, YF = line_factors(B, E, kl, mask, LINES)

    def f(t, q):
        a = jnp.asarray(a0) + 1e-6 * t * tilt
        _, p, al = solve_factored_cells(
            CellFactor(B, C, E, kl, mask, LINES, K_line, YF), a, q * jnp.asarray(b0), k, 100
        )
        return (jnp.sum((p / 100.0) ** 2) + jnp.sum(al**2) * 1e10) / 1e3

    x = (0.3, 1.1)
    h = 1e-6
    # compiled once each (eager calls compiled the solve's loops again at each call)
    fj = jax.jit(f)
    fd = [(fj(x[0] + h, x[1]) - fj(x[0] - h, x[1])) / (2 * h)]
    fd.append((fj(x[0], x[1] + h) - fj(x[0], x[1] - h)) / (2 * h))
    rev = jax.jit(jax.grad(f, argnums=(0, 1)))(*x)
    fwd = jax.jit(lambda t: jax.jvp(lambda s: f(s, x[1]), (t,), (1.0,))[1])(x[0])
    for g, d in zip(rev, fd, strict=True):
        assert float(g) == pytest.approx(float(d), rel=1e-6)
    assert float(fwd) == pytest.approx(float(fd[0]), rel=1e-6)


def test_vmapped_batch_factors_only_where_needed_and_equals_each_solve():
    """A batch mixing every kind (16 problems, 12 of them factored: two chunks of the gather
    under ``jax.vmap``), nested in an outer vmap over two loads: each answer equals its own
    reference solve, and the batched gradient each problem's own."""
    C, k, length, mask, E, kl, B = _problem(1, seed=5)
    K_line, YF = line_factors(B, E, kl, mask, LINES)
    z = np.linspace(0.0, 1.0, C_CELLS)
    gaps = [_gaps(kind, 1)[0] for kind in ("all", "line", "all", "line")]
    gaps += [5e-6 - (6e-6 + 0.4e-6 * i) * z**4 for i in range(8)]  # a few cells out
    gaps += [-4e-6 + (6e-6 + 0.5e-6 * i) * z**12 for i in range(4)]  # most cells out
    A = jnp.asarray(np.stack(gaps))
    loads = jnp.asarray([[60.0], [45.0]])

    def solve(a, b):
        factor = CellFactor(B, C, E, kl, mask, LINES, K_line, YF)
        _, p, al = solve_factored_cells(factor, a, b, k, 100)
        return p, al

    p, al = jax.jit(jax.vmap(jax.vmap(solve, (0, None)), (None, 0)))(A, loads)
    # each problem's own solve: one compiled program for the 32 (eager calls compiled the
    # solve's loops again at each call)
    reference = jax.jit(lambda a, b: jg.solve_contact_cells(
        jnp.asarray(C), a, jnp.asarray(E), b, jnp.asarray(k), jnp.asarray(length),
        jnp.asarray(mask), jg.ExactContact(),
    ))  # fmt: skip
    for j, b in enumerate(loads):
        for i, a in enumerate(A):
            _, p_ref, al_ref = reference(a, b)
            scale = np.abs(np.asarray(p_ref)).max()
            np.testing.assert_allclose(p[j, i], p_ref, rtol=0, atol=1e-12 * scale)
            np.testing.assert_allclose(al[j, i], al_ref, rtol=1e-12, atol=0)

    def energy(t, a):
        p, al = solve(a + 1e-6 * t * z, loads[0])
        return jnp.sum((p / 100.0) ** 2) / 1e3 + jnp.sum(al**2) * 1e7

    batched = jax.jit(jax.vmap(jax.grad(energy), (None, 0)))(0.2, A)
    grad_one = jax.jit(jax.grad(energy))  # each problem's own gradient, one program
    single = [float(grad_one(0.2, a)) for a in A]
    np.testing.assert_allclose(np.asarray(batched), single, rtol=1e-10)


# one compiled program for every batch below (the same shapes): the factored solve under vmap
# over gaps, and the reference solve of each problem
_C, _K, _LENGTH, _MASK, _E, _KL, _B = _problem(1, seed=7)
_FACTOR = CellFactor(_B, _C, _E, _KL, _MASK, LINES, *line_factors(_B, _E, _KL, _MASK, LINES))
_BATCHED = jax.jit(
    jax.vmap(lambda a, b: solve_factored_cells(_FACTOR, a, b, _K, 100)[1:], (0, None))
)
_REFERENCE = jax.jit(lambda a, b: jg.solve_contact_cells(
    jnp.asarray(_C), a, jnp.asarray(_E), b, jnp.asarray(_K), jnp.asarray(_LENGTH),
    jnp.asarray(_MASK), jg.ExactContact(),
)[1:])  # fmt: skip


@pytest.mark.parametrize("n_need", [0, 3, 8, 13, 20])
def test_factorisation_only_where_needed_under_vmap(n_need):
    """A batch of 20 problems of which ``n_need`` need a factorisation (a few cells out of
    contact: a Schur complement on them) and the others none (every cell in contact: products
    only): none, some, one chunk of 8 exactly, two chunks and every position of the gathered
    evaluation under vmap; each answer is its own reference solve's."""
    rng = np.random.default_rng(n_need)
    need = np.zeros(20, bool)
    need[rng.permutation(20)[:n_need]] = True
    z = np.linspace(0.0, 1.0, C_CELLS)
    rows = [
        5e-6 - (6e-6 + 0.3e-6 * i) * z**4 if need[i] else 5e-6 + (1e-8 + 1e-9 * i) * z
        for i in range(20)
    ]
    A = jnp.asarray(np.stack(rows))
    b = jnp.asarray([60.0])
    p, al = _BATCHED(A, b)
    for i, a in enumerate(A):
        p_ref, al_ref = _REFERENCE(a, b)
        in_contact = np.asarray(p_ref)[_MASK] > 0
        assert bool(np.all(in_contact)) != bool(need[i])  # the kind of problem intended
        scale = np.abs(np.asarray(p_ref)).max()
        np.testing.assert_allclose(p[i], p_ref, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(al[i], al_ref, rtol=1e-12, atol=0)
