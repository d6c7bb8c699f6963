"""The cell-space Newmark loop (:func:`jaxgear.dynamics.newmark` with a window of coordinates)
on a small synthetic structure against a separately written textbook Newmark: its records, the
steady-state window's records only (``keep_blocks``) and the divergence check paid once per
block (``block_check``), which must still fire on a run that blows up."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
from jaxgear.dynamics import LinearSystem, StepCells, newmark

N = 6  # coordinates
WINDOW = np.array([1, 3, 4])  # the cells see these (not contiguous: the gathers are exercised)


def _structure(alpha):
    """A grounded chain of six masses, mass-proportional damping C = α M (α < 0: the vibration
    grows), two cells on the window, always closed (δ0 far below the approach: a linear
    spring k l V Vᵀ), so that the contact problem has the closed form of a linear one."""
    m = np.array([1.0, 2.0, 1.5, 1.0, 2.5, 1.2])
    k = np.array([4.0, 3.0, 5.0, 2.0, 3.5, 4.5, 1.0]) * 1e4  # springs 0–1, …, 5–ground
    K = np.zeros((N, N))
    for i in range(N):  # spring i joins mass i−1 (ground for i = 0) to mass i
        K[i, i] += k[i]
        if i > 0:
            K[i - 1, i - 1] += k[i]
            K[i - 1, i] -= k[i]
            K[i, i - 1] -= k[i]
    K[N - 1, N - 1] += k[N]
    M = np.diag(m)
    C = alpha * M
    F = np.array([0.0, 50.0, 0.0, -20.0, 10.0, 0.0])
    V = np.array([[1.0, -0.5, 0.2], [0.3, 1.0, -0.8]])  # (c, w)
    kc, length = np.array([2e3, 3e3]), np.array([0.1, 0.1])  # soft: 200, 300 N/m
    delta0 = np.array([-1.0, -1.0])  # m: far more than the approach, the cells never open
    return K, M, C, F, V, kc, length, delta0


def _reference(K, M, C, F, V, kc, length, delta0, dt, n_steps):
    """Newmark average acceleration (β = 1/4, γ = 1/2) of M Ẍ + C Ẋ + K X + Vᵀ P = F with
    P = k l (V X_W − δ0) (the closed cells: a linear spring), from rest at X = 0 with the
    consistent acceleration; the textbook form (Hughes, *The Finite Element Method*, §9.1):
    predictors, then M a + C v + K d = F on the predicted state. Returns X, Ẋ per step."""
    E = np.zeros((V.shape[0], N))
    E[:, WINDOW] = V  # the cells' vectors on every coordinate
    kl = kc * length
    Kt = K + E.T @ (kl[:, None] * E)
    Ft = F + E.T @ (kl * delta0)
    d, v = np.zeros(N), np.zeros(N)
    a = np.linalg.solve(M, Ft - Kt @ d - C @ v)
    Xs, Vs = [], []
    for _ in range(n_steps):
        d_pred = d + dt * v + 0.25 * dt * dt * a
        v_pred = v + 0.5 * dt * a
        a = np.linalg.solve(M + 0.5 * dt * C + 0.25 * dt * dt * Kt, Ft - C @ v_pred - Kt @ d_pred)
        d = d_pred + 0.25 * dt * dt * a
        v = v_pred + 0.5 * dt * a
        Xs.append(d)
        Vs.append(v)
        assert np.all(E @ d - delta0 > 0.5)  # the cells stay closed: the law is this linear one
    return np.array(Xs), np.array(Vs), a


def _run(alpha, blocks, steps, dt, keep_blocks=None, bound=None):
    K, M, C, F, V, kc, length, delta0 = _structure(alpha)
    # the start of the reference: at rest, its consistent acceleration
    _, _, a0 = _reference(K, M, C, F, V, kc, length, delta0, dt, 0)
    row = jg.CellRow(
        jnp.asarray(WINDOW),
        jnp.asarray(V),
        jnp.asarray(kc),
        jnp.asarray(length),
        jnp.asarray(delta0),
        jnp.ones(2, bool),
    )
    Mj = jnp.asarray(M)

    def energy_check(X, Xd):  # ½ ẊᵀMẊ above the bound: the blow-up code
        return jnp.where(0.5 * Xd @ (Mj @ Xd) > bound, jg.DynamicsResult.blow_up, 0)

    state = (jnp.zeros(N), jnp.zeros(N), jnp.asarray(a0), jnp.array(0), jnp.array(0))
    return newmark(
        LinearSystem(jnp.asarray(K), Mj, jnp.asarray(C), jnp.asarray(F)),
        dt,
        state,
        jnp.zeros((blocks, steps), jnp.int32),
        StepCells(lambda _: row, jg.ExactContact()),
        lambda X, Xd, P, _: (X, Xd, P),
        checks=(None, None if bound is None else energy_check),
        keep_blocks=keep_blocks,
    )


def test_cell_space_records_only_the_kept_blocks_and_match_the_textbook_newmark():
    """The records of the last two of five blocks are the textbook Newmark's states at those
    steps (to 1e-12 of their scale), the contact forces its closed-cell springs' forces."""
    blocks, steps, dt = 5, 8, 2e-4
    K, M, C, F, V, kc, length, delta0 = _structure(-2.0)
    X_ref, Xd_ref, _ = _reference(K, M, C, F, V, kc, length, delta0, dt, blocks * steps)
    (X, _, _, code, _), (Xr, Xdr, P) = _run(-2.0, blocks, steps, dt, keep_blocks=2)
    assert int(code) == 0
    assert Xr.shape == (2 * steps, N)
    np.testing.assert_allclose(Xr, X_ref[-2 * steps :], rtol=0, atol=1e-12 * np.abs(X_ref).max())
    np.testing.assert_allclose(Xdr, Xd_ref[-2 * steps :], rtol=0, atol=1e-12 * np.abs(Xd_ref).max())
    P_ref = (kc * length) * (X_ref[-2 * steps :][:, WINDOW] @ V.T - delta0)
    np.testing.assert_allclose(P, P_ref, rtol=1e-11)
    np.testing.assert_allclose(X, X_ref[-1], rtol=0, atol=1e-12 * np.abs(X_ref).max())
    # every block recorded without keep_blocks
    assert _run(-2.0, blocks, steps, dt)[1][0].shape == (blocks * steps, N)


@pytest.mark.parametrize("kept", [None, 1])
def test_the_energy_check_once_per_block_still_fires_on_a_growing_run(kept):
    """Negative damping (α = −40 /s) makes the vibration grow; a kinetic-energy bound checked at
    the end of each block of 16 steps flags the blow-up code at the end of the block in which
    the textbook Newmark's energy first exceeds it, not before, whether or not the blocks are
    recorded."""
    steps, dt, alpha = 16, 2e-4, -40.0
    K, M, C, F, V, kc, length, delta0 = _structure(alpha)
    n_blocks = 40
    _, Xd_ref, _ = _reference(K, M, C, F, V, kc, length, delta0, dt, n_blocks * steps)
    ke = 0.5 * np.einsum("si,ij,sj->s", Xd_ref, M, Xd_ref)
    # a bound that the energy crosses for good in the middle of a block (ke grows ~e^{−α t})
    block_end = ke[steps - 1 :: steps]
    bound = float(np.sqrt(block_end[24] * block_end[25]))
    fire = int(np.argmax(ke > bound)) // steps  # the block in which it first crosses
    ends = np.nonzero(block_end > bound)[0]
    assert ends.size and 0 < ends[0] <= n_blocks - 2
    code_at = {}
    for b in (ends[0], ends[0] + 1):  # the block whose end first sees it over: fires there
        (_, _, _, code, _), _ = _run(alpha, int(b), steps, dt, keep_blocks=kept, bound=bound)
        code_at[int(b)] = int(code)
    assert fire <= ends[0]
    assert code_at[int(ends[0])] == 0  # the ends of blocks 1 … ends[0] are below the bound
    assert code_at[int(ends[0]) + 1] == jg.DynamicsResult.blow_up
