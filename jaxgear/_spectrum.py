"""Order spectrum of a transmission error over whole revolutions: mesh orders and the shaft-order
sidebands around them (docs/deviations.md, "Spectrum")."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import numpy as np

__all__ = ["TESpectrum", "te_spectrum"]


@dataclasses.dataclass(frozen=True)
class TESpectrum:
    """Single-sided amplitude spectrum of a TE in pinion shaft orders.

    Attributes:
        orders: pinion orders (events per pinion revolution) of the bins, (P//2 + 1,).
        amplitude: amplitude of each order (m): |X_m| / P at order 0 (the mean), 2 |X_m| / P
            above (a sine of amplitude A over whole periods reads A).
        revolutions: pinion revolutions spanned. teeth: (z1, z2).
    """

    orders: np.ndarray
    amplitude: np.ndarray
    revolutions: float
    teeth: tuple[int, int]

    def at(self, order: float) -> float:
        """Amplitude (m) of the bin nearest ``order``."""
        return float(self.amplitude[int(np.argmin(np.abs(self.orders - order)))])

    def lines(self, mesh_harmonics: int = 3) -> list[dict]:
        """The labelled lines: the pinion and gear shaft orders (1 and z1/z2) and, for the mesh
        harmonics h = 1 … ``mesh_harmonics``, the mesh order h z1 and its sidebands h z1 ± 1
        (pinion shaft) and h z1 ± z1/z2 (gear shaft). Each: ``label``, ``order`` (the asked
        order), ``bin_order`` (the nearest bin's), ``amplitude_m``."""
        z1, z2 = self.teeth
        g = Fraction(z1, z2)
        wanted = [("pinion shaft", Fraction(1)), ("gear shaft", g)]
        for h in range(1, mesh_harmonics + 1):
            m = Fraction(h * z1)
            name = "mesh" if h == 1 else f"{h}×mesh"
            wanted += [
                (f"{name} − pinion", m - 1),
                (f"{name} − gear", m - g),
                (name, m),
                (f"{name} + gear", m + g),
                (f"{name} + pinion", m + 1),
            ]
        out = []
        for label, order in wanted:
            i = int(np.argmin(np.abs(self.orders - float(order))))
            out.append(
                {
                    "label": label,
                    "order": float(order),
                    "bin_order": float(self.orders[i]),
                    "amplitude_m": float(self.amplitude[i]),
                }
            )
        return out


def te_spectrum(te, positions_per_pitch: int, teeth: tuple[int, int]) -> TESpectrum:
    """Amplitude spectrum of a TE sampled at equal pinion steps over whole mesh periods (as
    :func:`~jaxgear.mesh_positions` gives them), in pinion shaft orders.

    Args:
        te: transmission error (m), shape (P,), P = ``positions_per_pitch`` × periods.
        positions_per_pitch: positions per mesh period. teeth: (z1, z2).

    Returns:
        :class:`TESpectrum`. Over R = periods/z1 pinion revolutions the bins are 1/R orders apart:
        a gear order z1/z2 falls on a bin when R z1/z2 is an integer (the hunting period,
        :func:`~jaxgear.hunting_revolutions`, or whole gear revolutions).

    Raises:
        ValueError: a length that is not a whole number of mesh periods.
    """
    te = np.asarray(te, dtype=float)
    n = te.shape[0]
    if te.ndim != 1 or n % positions_per_pitch or n == 0:
        raise ValueError(
            f"te: {n} positions is out of range: allowed a whole number of mesh periods of "
            f"{positions_per_pitch} positions"
        )
    z1 = int(teeth[0])
    revolutions = n / positions_per_pitch / z1
    x = np.fft.rfft(te)
    amp = np.abs(x) / n
    amp[1:] *= 2.0
    if n % 2 == 0:
        amp[-1] /= 2.0  # the Nyquist bin has no mirror
    orders = np.arange(amp.shape[0]) / revolutions
    return TESpectrum(orders, amp, revolutions, (z1, int(teeth[1])))
