"""Exterior radiation by the boundary-element method (bempp-cl): the surface pressure of a closed
vibrating surface, its pressure at field points, and the formulations (kinds) that give it.

Time dependence e^{-iωt}; the fluid is outside the closed surface S, its normal n points into the
fluid; the normal velocity v (m/s) on the vertices gives the Neumann datum ∂p/∂n = iωρ v. With
the outgoing Green's function G = e^{ik|x-y|}/(4π|x-y|), the single layer V, the double layer K,
its adjoint K' and the hypersingular operator D = -∂/∂n K (bempp-cl's definitions), the
exterior pressure is the Helmholtz representation (Colton & Kress, *Integral Equation Methods in
Scattering Theory*, 1983, Thm. 3.1)

    p(x) = (K p)(x) - (V ∂p/∂n)(x),   x outside S,

whose trace gives the direct boundary integral equation (½I - K) p = -V ∂p/∂n. That equation
fails at the interior Dirichlet eigenfrequencies of S (the irregular frequencies); Burton &
Miller (Proc. R. Soc. A 323 (1971) 201) add α times its normal derivative,
D p = -(½I + K') ∂p/∂n:

    (½I - K + α D) p = -(V + α(½I + K')) ∂p/∂n,   α = i/k,

which is uniquely solvable at every real k. Both sides are assembled densely in the Galerkin
(P1 × P1) weak form by bempp-cl, the assembly O(n²) per frequency (the kernels hold k). With
test and trial functions from the same space the Galerkin matrix of K' is the plain transpose
of K's (swap x and y in ∫∫ φ_i ∂G/∂n_x φ_j: G is symmetric), so three operators are assembled
per frequency (V, K, D), not four. Where they are assembled is a :class:`BEMBackend`:
:class:`OpenCL` (bempp-cl's OpenCL kernels on PoCL, a CPU OpenCL driver: the default where it
imports) or :class:`Numba` (bempp-cl's numba kernels, compiled on first use in each process);
measured side by side in ``docs/acoustics.md``, "Time per frequency".

NumPy and bempp-cl (imported on first use); never JAX.
"""

from __future__ import annotations

import abc
import contextlib
import os
import warnings
from typing import ClassVar

import numpy as np
from tqdm import tqdm

from .._kinds import Kind
from ._surface import AIR, Fluid, RadiatingSurface

__all__ = [
    "BEMBackend",
    "BurtonMiller",
    "Direct",
    "Formulation",
    "Numba",
    "OpenCL",
    "bem_field_pressure",
    "bem_field_transfer",
    "bem_impedance",
    "bem_operators",
    "default_backend",
]


class Formulation(Kind):
    """A boundary integral formulation of the exterior Neumann problem (a kind: pass an
    instance; printed and compared by its name)."""

    @abc.abstractmethod
    def coupling(self, k: float) -> complex:
        """The Burton–Miller coupling α at wavenumber ``k`` (0: the plain direct equation)."""


class Direct(Formulation):
    """The direct equation (½I - K) p = -V ∂p/∂n alone: wrong near the irregular frequencies
    (for a sphere of radius a, ka = π, 4.49, …); kept for checks."""

    name = "direct"

    def coupling(self, k):
        return 0.0


class BurtonMiller(Formulation):
    """Burton–Miller: the direct equation plus α = i/k times its normal derivative (uniquely
    solvable at every frequency). The default."""

    name = "burton-miller"

    def coupling(self, k):
        return 1j / k


class BEMBackend(Kind):
    """Where bempp-cl assembles the dense boundary operators (a kind: pass an instance; printed
    and compared by its name). The backend changes the time, not the result (the operators
    agree to about 1e-12 relative in double precision), so the radiation cache's key does not
    hold it.

    Attributes:
        device_interface: bempp-cl's ``device_interface`` argument.
    """

    device_interface: ClassVar[str]

    def available(self, bempp) -> bool:
        """Whether this backend can assemble here (``bempp``: bempp_cl.api)."""
        return True

    @contextlib.contextmanager
    def session(self, bempp):
        """The bempp-cl settings in force while this backend assembles (none by default)."""
        yield


class Numba(BEMBackend):
    """bempp-cl's numba kernels: installed with bempp-cl on every platform, compiled on first
    use in each process (95 s of CPU on the benchmark's machine), then about twice OpenCL's
    time per assembly (``docs/acoustics.md``, "Time per frequency"). The default where no CPU
    OpenCL driver imports."""

    name = "numba"
    device_interface = "numba"


class OpenCL(BEMBackend):
    """bempp-cl's OpenCL kernels on a CPU OpenCL driver: ``pyopencl`` and PoCL
    (``pocl-binary-distribution``), installed with fem_prep on x86-64 Linux
    (``pyproject.toml``). The default where they import: about half numba's time per assembly
    and a ninth of its first use (``docs/acoustics.md``). Double precision, 4-wide vectors
    (AVX2's width: PoCL 3.0's 8-wide double kernels abort on CPUs without AVX-512); PoCL's own
    kernel cache is switched off before bempp-cl first loads the driver (with it on, PoCL 3.0
    returns programs without their kernels on a second build).

    Raises (on first use):
        RuntimeError: no pyopencl or no CPU OpenCL driver.
    """

    name = "opencl"
    device_interface = "opencl"

    def available(self, bempp):
        return bool(bempp.CPU_OPENCL_DRIVER_FOUND)

    @contextlib.contextmanager
    def session(self, bempp):
        if not self.available(bempp):
            raise RuntimeError(
                "BEM backend 'opencl': no CPU OpenCL driver found (pip install pyopencl "
                "pocl-binary-distribution), or use the default backend Numba()"
            )
        _keep_opencl_kernels()
        old = bempp.VECTORIZATION_MODE
        bempp.VECTORIZATION_MODE = "vec4"
        try:
            yield
        finally:
            bempp.VECTORIZATION_MODE = old


def _keep_opencl_kernels():
    """bempp-cl builds an OpenCL program at every assembly (seconds each with PoCL); its
    kernels depend on the operator, the spaces' sizes and the precision only, not on the
    wavenumber, so each is built once per process and kept (the same program serves every
    frequency of a surface). Built with ``-w``: PoCL's compiler otherwise prints its count of
    warnings (vector ABI notes) on the console at every build."""
    import bempp_cl.core.opencl_kernels as ok

    if getattr(ok.build_program, "_jaxgear_kept", False):
        return
    build = ok.build_program
    options_of = ok.get_kernel_compile_options
    kept: dict = {}
    ok.get_kernel_compile_options = lambda options, precision: [*options_of(options, precision), "-w"]

    def build_program(assembly_function, options, precision, device_type="cpu"):
        key = (assembly_function, tuple(sorted((k, repr(v)) for k, v in options.items())),
               precision, device_type)
        if key not in kept:
            kept[key] = build(assembly_function, options, precision, device_type)
        return kept[key]

    build_program._jaxgear_kept = True
    ok.build_program = build_program


#: the backends in the order of preference of :func:`default_backend` (fastest first:
#: ``docs/acoustics.md``, "Time per frequency")
PREFERENCE = (OpenCL, Numba)


def default_backend() -> BEMBackend:
    """The first of :data:`PREFERENCE` that is :meth:`~BEMBackend.available` here."""
    bempp = _bempp()
    return next(b() for b in PREFERENCE if b().available(bempp))


def _check_backend(backend, fn):
    backend = default_backend() if backend is None else backend
    if not isinstance(backend, BEMBackend):
        raise TypeError(f"{fn}: backend must be a BEMBackend (Numba(), OpenCL()), got {backend!r}")
    return backend


def _check(surface, frequency_hz, fluid, formulation, fn):
    if not isinstance(surface, RadiatingSurface):
        raise TypeError(f"{fn}: surface must be a RadiatingSurface, got {type(surface).__name__}")
    if not surface.closed:
        raise ValueError(
            f"{fn}: the exterior BEM needs a closed surface (every edge in 2 triangles)"
        )
    if not isinstance(fluid, Fluid):
        raise TypeError(f"{fn}: fluid must be a Fluid, got {type(fluid).__name__}")
    if not isinstance(formulation, Formulation):
        raise TypeError(
            f"{fn}: formulation must be a Formulation (BurtonMiller(), Direct()), "
            f"got {formulation!r}"
        )
    return fluid.wavenumber(frequency_hz)


@contextlib.contextmanager
def _quiet():
    """bempp-cl's own warnings silenced: its import warns of a SciPy namespace it uses,
    numba's compile of its kernels of non-contiguous arrays (NumbaPerformanceWarning) and
    pyopencl of PoCL's compiler remarks."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", module=r"bempp_cl\.")
        warnings.filterwarnings("ignore", category=DeprecationWarning, message=".*scipy")
        warnings.filterwarnings("ignore", message=".*faster on contiguous arrays")
        # pyopencl on PoCL's remarks while building bempp-cl's kernels (vector ABI notes)
        warnings.filterwarnings("ignore", message="Non-empty compiler output")
        yield


def _bempp():
    """bempp_cl.api, imported on first use (PoCL's kernel cache off first: see :class:`OpenCL`)."""
    os.environ.setdefault("POCL_KERNEL_CACHE", "0")
    with _quiet():
        import bempp_cl.api as bempp
    return bempp


def _space(surface):
    bempp = _bempp()

    with _quiet():
        grid = bempp.Grid(surface.vertices.T.copy(), surface.triangles.T.astype(np.uint32))
        space = bempp.function_space(grid, "P", 1)
    # bempp numbers the P1 dofs itself: dof[i] is the dof of vertex i
    dof = np.full(surface.n_vertices, -1)
    dof[surface.triangles.ravel()] = np.asarray(space.local2global).ravel()
    if space.global_dof_count != surface.n_vertices or sorted(dof) != list(range(len(dof))):
        raise ValueError("RadiatingSurface: a vertex in no triangle (bempp's P1 space skips it)")
    return bempp, space, dof


def bem_impedance(
    surface: RadiatingSurface,
    frequency_hz: float,
    fluid: Fluid = AIR,
    formulation: Formulation | None = None,
    *,
    progress: bool = False,
    backend: BEMBackend | None = None,
) -> np.ndarray:
    """The surface impedance matrix Z of a closed radiating surface: p = Z v on the vertices.

    Args:
        surface: a closed :class:`RadiatingSurface` (normals outward, into the fluid).
        frequency_hz: f > 0 (Hz).
        fluid: the medium outside.
        formulation: :class:`BurtonMiller` (default) or :class:`Direct`.
        progress: a tqdm bar over the operator assemblies and the solve.
        backend: where bempp-cl assembles: :class:`Numba` or :class:`OpenCL` (``None``:
            :func:`default_backend`).

    Returns:
        ``(n, n)`` complex Z (Pa s/m): the vertex pressure amplitudes (Pa, peak, e^{-iωt}) for
        vertex normal velocity amplitudes v (m/s).

    Raises:
        TypeError: a surface, fluid, formulation or backend of another type.
        ValueError: an open surface, ``frequency_hz`` ≤ 0.
        RuntimeError: :class:`OpenCL` without a CPU OpenCL driver.
    """
    formulation = BurtonMiller() if formulation is None else formulation
    k = _check(surface, frequency_hz, fluid, formulation, "bem_impedance")
    backend = _check_backend(backend, "bem_impedance")
    ops = bem_operators(surface, k, with_hypersingular=formulation.coupling(k) != 0,
                        backend=backend, progress=progress, label=f"BEM {frequency_hz:.6g} Hz")
    alpha = formulation.coupling(k)
    ident, K = ops["identity"], ops["double_layer"]
    lhs = 0.5 * ident - K
    rhs = -ops["single_layer"]
    if alpha != 0:
        lhs = lhs + alpha * ops["hypersingular"]
        rhs = rhs - alpha * (0.5 * ident + K.T)  # K' = Kᵀ (the module's note)
    omega = 2 * np.pi * frequency_hz
    return 1j * omega * fluid.density * np.linalg.solve(lhs, rhs)


def bem_operators(
    surface: RadiatingSurface,
    wavenumber: float,
    *,
    with_hypersingular: bool = True,
    with_adjoint: bool = False,
    backend: BEMBackend | None = None,
    progress: bool = False,
    label: str = "BEM",
) -> dict[str, np.ndarray]:
    """The dense Galerkin (P1 × P1) matrices of the Helmholtz boundary operators on the
    vertices of a closed surface, in the vertex order: ``"identity"`` (the mass matrix, m²),
    ``"single_layer"`` V, ``"double_layer"`` K and (``with_hypersingular``) ``"hypersingular"``
    D at ``wavenumber`` k (1/m), bempp-cl's definitions (the module's note), and
    (``with_adjoint``, for checks: the solve takes K' = Kᵀ) ``"adjoint_double_layer"`` K'.

    Raises:
        TypeError: a backend of another type. RuntimeError: as :func:`bem_impedance`.
    """
    backend = _check_backend(backend, "bem_operators")
    bempp, sp, dof = _space(surface)
    b = bempp.operators.boundary
    ix = np.ix_(dof, dof)  # the vertex order
    names = ["single_layer", "double_layer"] + (["hypersingular"] if with_hypersingular else [])
    names += ["adjoint_double_layer"] if with_adjoint else []
    with tqdm(total=len(names) + 1, desc=label, disable=not progress) as bar:

        def weak(op):
            with _quiet():
                a = op.weak_form().to_dense()
            bar.update()
            return np.asarray(a)[ix]

        with backend.session(bempp):
            out = {"identity": weak(b.sparse.identity(sp, sp, sp))}
            for n in names:
                op = getattr(b.helmholtz, n)(
                    sp, sp, sp, wavenumber, device_interface=backend.device_interface
                )
                out[n] = weak(op)
    return out


def bem_field_pressure(
    surface: RadiatingSurface,
    frequency_hz: float,
    velocity: np.ndarray,
    points: np.ndarray,
    fluid: Fluid = AIR,
    formulation: Formulation | None = None,
    impedance: np.ndarray | None = None,
) -> np.ndarray:
    """The pressure amplitude (Pa, peak, e^{-iωt}) at field points (microphones) outside a
    closed surface vibrating with vertex normal velocity ``velocity`` ``(n,)`` (m/s): the
    representation p = K p_S - V ∂p/∂n with the surface pressure p_S = Z v.

    Args:
        surface, frequency_hz, fluid, formulation: as :func:`bem_impedance`.
        velocity: ``(n,)`` complex normal velocity amplitudes on the vertices (m/s).
        points: ``(q, 3)`` field points (m), outside the surface.
        impedance: Z from :func:`bem_impedance` at this frequency (computed if ``None``).

    Returns:
        ``(q,)`` complex pressure amplitudes (Pa).

    Raises:
        TypeError, ValueError: as :func:`bem_impedance`; shapes that do not fit.
    """
    formulation = BurtonMiller() if formulation is None else formulation
    k = _check(surface, frequency_hz, fluid, formulation, "bem_field_pressure")
    v = np.asarray(velocity)
    if v.shape != (surface.n_vertices,):
        raise ValueError(
            f"bem_field_pressure: velocity must be ({surface.n_vertices},), got {v.shape}"
        )
    x = np.asarray(points, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3 or not np.all(np.isfinite(x)):
        raise ValueError(f"bem_field_pressure: points must be finite (q, 3), got {x.shape}")
    if impedance is None:
        impedance = bem_impedance(surface, frequency_hz, fluid, formulation)
    if np.shape(impedance) != (surface.n_vertices,) * 2:
        raise ValueError(f"bem_field_pressure: impedance must be (n, n), got {np.shape(impedance)}")
    bempp, sp, dof = _space(surface)
    omega = 2 * np.pi * frequency_hz
    p_s, q = np.zeros(len(dof), complex), np.zeros(len(dof), complex)
    p_s[dof] = np.asarray(impedance) @ v
    q[dof] = 1j * omega * fluid.density * v
    p_s, q = bempp.GridFunction(sp, coefficients=p_s), bempp.GridFunction(sp, coefficients=q)
    pot = bempp.operators.potential.helmholtz
    with _quiet():
        p = pot.double_layer(sp, x.T, k, device_interface="numba").evaluate(p_s)
        p = p - pot.single_layer(sp, x.T, k, device_interface="numba").evaluate(q)
    return np.asarray(p).reshape(-1)


def bem_field_transfer(
    surface: RadiatingSurface,
    frequency_hz: float,
    impedance: np.ndarray,
    points: np.ndarray,
    fluid: Fluid = AIR,
) -> np.ndarray:
    """The matrix T with p(x) = T v: the pressure amplitudes (Pa, peak, e^{-iωt}) at field
    points (microphones) per unit vertex normal velocity (m/s) of a closed surface, the
    representation p = K p_S − V ∂p/∂n of :func:`bem_field_pressure` with p_S = Z v and
    ∂p/∂n = iωρ v, integrated in NumPy by each triangle's 3-point rule
    (:meth:`RadiatingSurface.quadrature`) instead of bempp-cl's potentials (which give one
    velocity at a time):

        T = (∂G/∂n_y)(x, y_q) w_q Φ Z − G(x, y_q) w_q Φ iωρ,
        G = e^{ikr}/(4πr),  ∂G/∂n_y = (n_y · (x − y)/r) (1/r − ik) G.

    Accurate for points a few triangle sizes off the surface (microphones).

    Args:
        surface: a closed :class:`RadiatingSurface`.
        frequency_hz: f > 0 (Hz).
        impedance: ``(n, n)`` Z from :func:`bem_impedance` at this frequency.
        points: ``(q, 3)`` field points (m), outside the surface.
        fluid: the medium.

    Returns:
        ``(q, n)`` complex T (Pa s/m).

    Raises:
        TypeError, ValueError: as :func:`bem_impedance`; shapes that do not fit.
    """
    k = _check(surface, frequency_hz, fluid, BurtonMiller(), "bem_field_transfer")
    x = np.asarray(points, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3 or not np.all(np.isfinite(x)):
        raise ValueError(f"bem_field_transfer: points must be finite (q, 3), got {x.shape}")
    if np.shape(impedance) != (surface.n_vertices,) * 2:
        raise ValueError(f"bem_field_transfer: impedance must be (n, n), got {np.shape(impedance)}")
    y, w, interp = surface.quadrature()
    ny = np.repeat(surface.normals, 3, axis=0)
    d = x[:, None, :] - y[None, :, :]
    r = np.linalg.norm(d, axis=2)
    g = np.exp(1j * k * r) / (4 * np.pi * r)
    dg = np.einsum("qpd,pd->qp", d, ny) / r * (1 / r - 1j * k) * g
    a = interp * w[:, None]
    omega = 2 * np.pi * frequency_hz
    return (dg @ a) @ np.asarray(impedance) - 1j * omega * fluid.density * (g @ a)
