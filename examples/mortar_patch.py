"""Mortar patch test (seed II-21/22, docs/hybrid.md, "Mortar patch test"): contact cells on a non-matching FE face.

A 2-D plane-strain block (x across the face width, y the depth; lateral rollers u_x = 0 on the
sides, u_y = 0 at the bottom; E = 210 GPa, ν = 0.3) is pressed on its top face by N_DE discrete
elements (the contact cells, "slices" of width Δ), each carrying the load f·Δ of a uniform line
force f. The cells see the top face through interface weights A (n_cells × n_masters): the load
of the block is Aᵀ (f Δ) and the cell displacements q = A u_top. The exact solution is the
uniform compression of a laterally confined layer: σ_yy = −f, ε_xx = ε_zz = 0, so
u_y(top) = −f h / M with the oedometric modulus M = E (1 − ν) / ((1 + ν)(1 − 2ν)).

Interfaces (a cell [a, b], centre c, Δ = b − a):

* ``collocation``: the face interpolated at the cell centre only;
* ``mortar``: the Simpson rule (2.26) on the cell, ``jaxgear.scenes.mortar_weights()`` on the
  face interpolated at a, c, b — jaxgear's interface;
* ``split``: the Simpson rule on each piece of the cell between FE element ends (a reference:
  exact for a face that is polynomial on each element up to degree 3).

Faces: as jaxgear's rim faces, the face is interpolated *linearly* between the corner nodes of
the elements (the axial part of ``FlexibleMember.face_weights``, used here on a dummy member
whose axial master planes are the element ends). ``Q4`` (bilinear elements) is the consistent
case; ``Q8`` (serendipity) with the same corner-only interface is what fem_prep's hex20 rim
faces condensed on their corner nodes give (docs/hybrid.md, "Seed typos and traps"); ``Q8-quadratic`` interpolates the face
quadratically on all three nodes of each element edge (corner and mid-side) — the construction
of the 2-D reference table of docs/hybrid.md, "Mortar patch test".

Run: ``python examples/mortar_patch.py [out_dir]`` (default ``docs/bench``): writes
``mortar_patch.png`` (q / q_exact across the face for a nested and a non-nested layout) and
``mortar_patch.json`` (max |q/q_exact − 1| for the reference layouts of docs/hybrid.md).
"""

from __future__ import annotations

import dataclasses
import json
import sys
from functools import cache
from pathlib import Path

import jax
import numpy as np
import skfem
from skfem.models.elasticity import lame_parameters, linear_elasticity

from jaxgear.scenes import FlexibleMember, mortar_weights

jax.config.update("jax_enable_x64", True)

E = 210e9  # Pa
NU = 0.3
WIDTH = 0.020  # m, the top face (x)
DEPTH = 0.010  # m, the block depth h (y): h = width / 2 as the reference of docs/hybrid.md
N_DEPTH = 2  # elements in depth (the reference of docs/hybrid.md)
LOAD = 1.0e8  # N/m²: the line force f per unit width of the face, per unit thickness
ELEMENTS = ("Q4", "Q8", "Q8-quadratic")
INTERFACES = ("collocation", "mortar", "split")
LAYOUTS = (
    (4, 7),
    (3, 8),
    (4, 8),
)  # FE elements × DE cells across the face (docs/hybrid.md, "Mortar patch test")


def exact_displacement(f=LOAD, h=DEPTH, E=E, nu=NU):
    """u_y of the top face of a laterally confined plane-strain layer under the pressure f (m,
    negative = down): −f h (1 + ν)(1 − 2ν) / (E (1 − ν))."""
    return -f * h * (1.0 + nu) * (1.0 - 2.0 * nu) / (E * (1.0 - nu))


def _member(x_nodes) -> FlexibleMember:
    """A FlexibleMember whose axial master planes are the FE element ends. Only the axial part
    of ``face_weights`` is used: every other field is a dummy (1 for the scalars, one station for
    the DOF tables), filled by name so that the member's other fields may change."""
    n = len(x_nodes)
    special = {
        "centre": np.zeros(3),
        "rim_dofs": np.zeros((1, n, 3), np.int32),
        "body_dofs": np.zeros(1, np.int32),
        "z_nodes": np.asarray(x_nodes, float),
        "n_window": 1,
    }
    values = {f.name: special.get(f.name, 1.0) for f in dataclasses.fields(FlexibleMember)}
    return FlexibleMember(**values)


@jax.jit
def _axial_weights(member, points):
    """Axial face j and the weights of nodes j, j + 1 (summed over the two stations)."""
    phi = member.station0 + 0.5 * member.pitch_angle + 0.0 * points  # mid-station
    j, w = member.face_weights(phi, points)[1:3]
    return j, w.sum(axis=-2)


def linear_face(x_nodes, points):
    """Weights (n_points, n_nodes) of the face interpolated linearly between the element ends
    ``x_nodes``, at ``points``: jaxgear's axial face interpolation (``FlexibleMember.face_weights``
    summed over the two stations)."""
    points = np.asarray(points, float).ravel()
    padded = np.zeros(-(-points.size // 128) * 128)  # few shapes: few compilations
    padded[: points.size] = points
    j, wz = _axial_weights(_member(x_nodes), padded)
    j, wz = np.asarray(j)[: points.size], np.asarray(wz)[: points.size]
    A = np.zeros((points.size, len(x_nodes)))
    rows = np.arange(points.size)
    np.add.at(A, (rows, j), wz[:, 0])
    np.add.at(A, (rows, j + 1), wz[:, 1])
    return A


def quadratic_face(x_nodes, points):
    """Weights (n_points, 2 n_el + 1) of the face interpolated quadratically on each element
    (corner, mid-side, corner nodes in x order): the Q8 face with all its nodes."""
    x_nodes, points = np.asarray(x_nodes, float), np.asarray(points, float)
    n_el = len(x_nodes) - 1
    e = np.clip(np.searchsorted(x_nodes, points, side="right") - 1, 0, n_el - 1)
    s = 2.0 * (points - x_nodes[e]) / (x_nodes[e + 1] - x_nodes[e]) - 1.0  # −1 … 1
    A = np.zeros((points.size, 2 * n_el + 1))
    rows = np.arange(points.size)
    for k, nk in enumerate((0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0))):
        A[rows, 2 * e + k] += nk
    return A


def interface(x_nodes, n_cells, kind, face=linear_face, width=WIDTH):
    """Interface matrix A (n_cells, n_masters) of ``n_cells`` equal cells on [0, width]."""
    edges = np.linspace(0.0, width, n_cells + 1)
    a, b = edges[:-1], edges[1:]
    c = 0.5 * (a + b)
    if kind == "collocation":
        return face(x_nodes, c)
    m1, m2, m3 = mortar_weights()
    if kind == "mortar":
        fa, fc, fb = np.split(face(x_nodes, np.concatenate([a, c, b])), 3)
        return m1 * fa + m2 * fc + m3 * fb
    if kind != "split":
        raise ValueError(kind)
    # the pieces of every cell between element ends, then Simpson on each piece
    cell, p, q = [], [], []
    for k, (lo, hi) in enumerate(zip(a, b)):
        cuts = np.unique(np.concatenate([[lo, hi], x_nodes[(x_nodes > lo) & (x_nodes < hi)]]))
        cell += [k] * (len(cuts) - 1)
        p += list(cuts[:-1])
        q += list(cuts[1:])
    cell, p, q = np.array(cell), np.array(p), np.array(q)
    fp, fm, fq = np.split(face(x_nodes, np.concatenate([p, 0.5 * (p + q), q])), 3)
    pieces = ((q - p) / (b - a)[cell])[:, None] * (m1 * fp + m2 * fm + m3 * fq)
    A = np.zeros((n_cells, len(fp[0])))
    np.add.at(A, cell, pieces)
    return A


@cache
def block(n_el: int, element: str, depth: float = DEPTH, n_depth: int = N_DEPTH):
    """The FE block of ``n_el`` × ``n_depth`` elements: (stiffness K, free DOFs, the top-face
    y DOFs of the masters and their x positions (x order), the element ends, the DOF
    locations (2, n_dofs))."""
    x_nodes = np.linspace(0.0, WIDTH, n_el + 1)
    mesh = skfem.MeshQuad.init_tensor(x_nodes, np.linspace(0.0, depth, n_depth + 1))
    elem = skfem.ElementQuad1() if element == "Q4" else skfem.ElementQuadS2()
    basis = skfem.Basis(mesh, skfem.ElementVector(elem))
    lam, mu = lame_parameters(E, NU)  # plane strain: the 3-D Lamé parameters
    K = skfem.asm(linear_elasticity(lam, mu), basis)
    sides = basis.get_dofs(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], WIDTH))
    bottom = basis.get_dofs(lambda x: np.isclose(x[1], 0.0))
    fixed = np.union1d(sides.all("u^1"), bottom.all("u^2"))
    free = np.setdiff1d(np.arange(basis.N), fixed)
    top = basis.get_dofs(lambda x: np.isclose(x[1], depth))
    if element == "Q8-quadratic":
        dofs = top.all("u^2")  # corner and mid-side nodes
    else:
        dofs = top.nodal["u^2"]  # corner nodes only: the linear face
    xs = basis.doflocs[0, dofs]
    order = np.argsort(xs)
    return K, free, dofs[order], xs[order], x_nodes, basis.doflocs


def fe_solve(n_el, n_cells, element="Q4", kind="mortar", depth=DEPTH, n_depth=N_DEPTH, f=LOAD):
    """The patch test: cell displacements q / q_exact (n_cells,), the FE displacement vector
    (n_dofs,) and the DOF locations (2, n_dofs) (x and y components interleaved)."""
    K, free, dofs, _, x_nodes, locs = block(n_el, element, depth, n_depth)
    face = quadratic_face if element == "Q8-quadratic" else linear_face
    A = interface(x_nodes, n_cells, kind, face)
    load = np.zeros(K.shape[0])
    load[dofs] = A.T @ np.full(n_cells, -f * WIDTH / n_cells)  # Aᵀ (f Δ), downwards
    u = skfem.solve(*skfem.condense(K, load, I=free))
    return (A @ u[dofs]) / exact_displacement(f, depth), u, locs


def solve(n_el, n_cells, element="Q4", kind="mortar", depth=DEPTH, n_depth=N_DEPTH):
    """Cell displacements q / q_exact (n_cells,)."""
    return fe_solve(n_el, n_cells, element, kind, depth, n_depth)[0]


def max_error(n_el, n_cells, element="Q4", kind="mortar", depth=DEPTH, n_depth=N_DEPTH):
    """max |q / q_exact − 1| over the cells."""
    return float(np.abs(solve(n_el, n_cells, element, kind, depth, n_depth) - 1.0).max())


def table():
    """{element: {"FExDE": {interface: max |q/q_exact − 1|}}} for the reference layouts of docs/hybrid.md."""
    return {
        el: {f"{n}x{m}": {k: max_error(n, m, el, k) for k in INTERFACES} for n, m in LAYOUTS}
        for el in ELEMENTS
    }


def main(out_dir="docs/bench"):
    """Write ``mortar_patch.json`` and ``mortar_patch.png`` to ``out_dir``; return the table."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    res = table()
    meta = {
        "seed": "II-21/22, docs/hybrid.md, Mortar patch test",
        "block": {
            "width_m": WIDTH,
            "depth_m": DEPTH,
            "elements_in_depth": N_DEPTH,
            "E_Pa": E,
            "nu": NU,
            "line_force_N_per_m2": LOAD,
            "plane": "strain; lateral rollers, u_y = 0 at the bottom",
        },
        "q_exact_m": exact_displacement(),
        "measure": "max over the cells of |q/q_exact - 1|",
        "elements": {
            "Q4": "bilinear elements, face linear between corner nodes (jaxgear's rim faces)",
            "Q8": "serendipity elements, interface on the corner nodes only (linear face)",
            "Q8-quadratic": "serendipity elements, face quadratic on all 3 edge nodes "
            "(the reference table of docs/hybrid.md)",
        },
        "layouts": "FE elements x DE cells across the face",
    }
    text = json.dumps({"meta": meta, "errors": res}, indent=1, ensure_ascii=False)
    (out / "mortar_patch.json").write_text(text + "\n", encoding="utf-8")

    styles = {
        "collocation": {"color": "C3", "marker": "o", "ms": 9, "ls": "-"},
        "mortar": {"color": "C0", "marker": "s", "ms": 6, "ls": "-"},
        "split": {"color": "C2", "marker": "^", "ms": 5, "ls": "--"},
    }
    panels = (("Q4", "linear faces (jaxgear)"), ("Q8-quadratic", "quadratic faces (reference)"))
    layouts = ((4, 8, "nested"), (4, 7, "non-nested"))
    fig, axes = plt.subplots(2, 2, figsize=(12, 8), sharex=True)
    for row, (el, el_title) in zip(axes, panels):
        for ax, (n, m, lay) in zip(row, layouts):
            xc = (np.arange(m) + 0.5) * WIDTH / m * 1e3
            for k in INTERFACES:
                err = res[el][f"{n}x{m}"][k]
                ax.plot(xc, solve(n, m, el, k), **styles[k], label=f"{k}: max error {err:.2%}")
            for i, xe in enumerate(np.linspace(0.0, WIDTH, n + 1) * 1e3):
                label = "FE element ends" if i == 0 else None
                ax.axvline(xe, color="0.4", lw=1.0, ls=":", label=label)
            cells = np.linspace(0.0, WIDTH, m + 1) * 1e3
            ax.plot(
                cells,
                np.zeros_like(cells),
                "|",
                color="k",
                ms=10,
                mew=1.2,
                transform=ax.get_xaxis_transform(),
                clip_on=False,
                label="cell ends",
            )
            ax.set_title(f"{el_title}: {n} elements × {m} cells, {lay}", fontsize=10)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8, loc="upper center")
            ax.set_ylabel("q / q_exact (–)")
        lo = min(line.get_ydata().min() for ax in row for line in ax.get_lines()[:3])
        hi = max(line.get_ydata().max() for ax in row for line in ax.get_lines()[:3])
        pad = max(0.25 * (hi - lo), 0.01)
        for ax in row:
            ax.set_ylim(lo - pad, hi + 2.5 * pad)
    for ax in axes[-1]:
        ax.set_xlabel("x across the face (mm)")
    fig.suptitle(
        "Mortar patch test (seed II-21/22): cell displacement under a uniform line load, "
        "plane-strain block, E = 210 GPa, ν = 0.3"
    )
    fig.tight_layout()
    fig.savefig(out / "mortar_patch.png", dpi=110)
    plt.close(fig)
    return res


if __name__ == "__main__":
    result = main(sys.argv[1] if len(sys.argv) > 1 else "docs/bench")
    for el, rows in result.items():
        for lay, errs in rows.items():
            print(f"{el:13s} {lay}", "  ".join(f"{k} {v:.3%}" for k, v in errs.items()))
