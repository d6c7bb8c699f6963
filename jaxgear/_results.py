"""Result codes of the iterative solvers, as enumerations with messages (like diffrax's RESULTS).

The solvers store codes as integer arrays (they are vmapped, scanned and differentiated); these
enumerations give them names and human-readable messages::

    res = jg.quasi_static(mesh, mods, torque, throw=False)
    for code in set(res.result.tolist()):
        print(jg.ContactResult(code).message)
"""

from __future__ import annotations

import enum

import equinox as eqx
import jax.numpy as jnp
import numpy as np

__all__ = [
    "ContactResult",
    "CutterResult",
    "DynamicsResult",
    "error_if_failed",
    "raise_if_failed",
]


class _Result(enum.IntEnum):
    """An integer result code with a message (0 is success)."""

    @property
    def message(self) -> str:
        return _MESSAGES[type(self).__name__][self.value]

    @classmethod
    def messages(cls) -> dict[int, str]:
        """Code → message, JSON-ready (``{str(code): message}`` after ``str``)."""
        return dict(_MESSAGES[cls.__name__])


class ContactResult(_Result):
    """Outcome of one contact solve (:func:`jaxgear.solve_contact`, :func:`jaxgear.quasi_static`)."""

    successful = 0
    max_iterations = 1
    no_contact = 2
    non_finite = 3
    beyond_extension = 4


class DynamicsResult(_Result):
    """Outcome of a dynamic simulation at one speed, lumped or hybrid
    (:func:`jaxgear.dynamics.simulate`, :func:`jaxgear.dynamics.speed_sweep`)."""

    successful = 0
    contact_not_converged = 1
    non_finite = 2
    blow_up = 3
    ode_failed = 4
    window_overflow = 5


class CutterResult(_Result):
    """Whether a pinion-type cutter can generate an internal gear's fillet up to its 60° section
    (:meth:`jaxgear.rating.ShaperCutterSection.result`; where it cannot, the section is NaN)."""

    successful = 0
    no_cutting_mesh = 1
    rounding_below_base_circle = 2
    pointed_tip = 3
    rounding_inside_pitch_circle = 4


def error_if_failed(x, result, enum_cls: type[_Result], where: str):
    """``x``, raising ``eqx.EquinoxRuntimeError`` ``"{where}: {message}"`` when any entry of
    the integer array ``result`` holds a failure code of ``enum_cls`` (``eqx.error_if``: raises
    eagerly and under jit, vmap and grad alike; the message names the first failing code).

    Args:
        x: an array to carry the check (returned unchanged in value).
        result: result codes, any shape. enum_cls: :class:`ContactResult` or
            :class:`DynamicsResult`. where: the function's name, for the message.
    """
    for code in enum_cls:
        if code:
            x = eqx.error_if(x, jnp.any(jnp.asarray(result) == code), f"{where}: {code.message}")
    return x


def raise_if_failed(result, enum_cls: type[_Result], where: str) -> None:
    """The host-side twin of :func:`error_if_failed` for a concrete ``result`` (outside any
    trace): raise ``eqx.EquinoxRuntimeError`` ``"{where}: {message}"`` of the first failing
    code. A compiled program that holds ``eqx.error_if`` carries a Python callback, which JAX's
    persistent compilation cache does not store; a check made here keeps it out."""
    codes = np.asarray(result)
    for code in enum_cls:
        if code and np.any(codes == code):
            raise eqx.EquinoxRuntimeError(f"{where}: {code.message}")


_MESSAGES = {
    "ContactResult": {
        0: "converged",
        1: "contact loop did not converge at max_iterations (exact: active set still changing;"
        " smooth: Newton residual above its round-off tolerance)",
        2: "no cell in contact (zero mesh stiffness): check the load and the deviations",
        3: "non-finite state in the contact solve",
        4: "contact reaches the end of the cells beyond the theoretical path (extended_contact:"
        " the deflection closes the tip-corner gap there, max(3 % of the normal module,"
        " 100 µm)): check the load",
    },
    "DynamicsResult": {
        0: "converged",
        1: "contact loop did not converge at some time step (active set still changing, or"
        " smooth Newton residual above its round-off tolerance, at max_iterations)",
        2: "non-finite state: the integration diverged",
        3: "energy blow-up: vibration energy or mesh force beyond the divergence bound",
        4: "ODE solver failed (max_steps reached or step size collapsed)",
        5: "a contact cell left the window of master DOFs that the mesh damping updates"
        " (an internal error of the hybrid scene's window estimate)",
    },
    "CutterResult": {
        0: "the cutter generates the fillet",
        1: "no cutting mesh: inv α_w0 = inv α_n + 2 tan α_n (x0 + x2)/(z0 − |z2|) <= 0 (the"
        " profile shifts too large for the tooth-count difference)",
        2: "the cutter's tip rounding ends below its base circle (its tip circle, set to cut the"
        " ring's root circle, is too low for an involute above the rounding)",
        3: "the cutter's tooth is pointed at the tip circle that cuts the ring's root circle"
        " (its two tip roundings overlap)",
        4: "the centre of the cutter's tip rounding lies inside the cutting mesh's pitch circle:"
        " the rounding does not generate the fillet up to its 60° tangent (the internal"
        " analogue of ISO 6336-3's G < 0 of the generating rack)",
    },
}
