"""Gear whine's figures (``jaxgear run`` with ``[whine]``): the order plot (each order's
amplitude against speed) and the waterfall (speed against frequency, each order's level in
colour), the speeds where the linear result does not hold shaded."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import Normalize

from ._figure import new_figure, savefig

__all__ = ["whine_level_plot", "whine_order_plot", "whine_waterfall_plot"]

#: the linear result's caveat, under the axes where some speed is flagged
INVALID_NOTE = "shaded: contact loss, the linear (frequency-domain) result does not hold there"


def _shade(ax, speeds, invalid) -> bool:
    """Shade the speed intervals around flagged speeds; whether any was."""
    s = np.asarray(speeds, dtype=float)
    bad = np.asarray(invalid, dtype=bool)
    if not bad.any():
        return False
    half = np.diff(s, prepend=s[0] - (s[1] - s[0])) / 2 if s.size > 1 else np.array([1.0])
    for k in np.nonzero(bad)[0]:
        lo = s[k] - half[k]
        hi = s[k] + (half[k + 1] if k + 1 < s.size else half[k])
        ax.axvspan(lo, hi, color="tab:red", alpha=0.15, lw=0)
    return True


def whine_order_plot(path, speeds, amplitudes, orders, *, ylabel, title, invalid=None,
                     note=None, order_labels=None) -> None:
    """Each order's amplitude against the speed, log scale.

    Args:
        speeds: (S,) input speeds (rad/s). amplitudes: (S, k) one-sided amplitudes (in the
            units ``ylabel`` states) of the orders ``orders`` (k,).
        invalid: None or (S,) booleans: speeds where the linear result does not hold (shaded).
        order_labels: None (each line named "order <o>") or (k,) the legend's names.
    """
    fig, ax = new_figure()
    a = np.asarray(amplitudes, dtype=float)
    for j, o in enumerate(orders):
        ax.semilogy(speeds, np.maximum(a[:, j], 1e-300), "-", lw=1.3, marker=".", ms=3,
                    label=f"order {o:g}" if order_labels is None else order_labels[j])
    top = float(np.nanmax(a)) if a.size else 1.0
    ax.set_ylim(max(top * 1e-4, float(np.nanmin(a[a > 0])) if (a > 0).any() else top * 1e-4),
                top * 2.0)
    flagged = invalid is not None and _shade(ax, speeds, invalid)
    ax.set_xlabel("input speed (rad/s)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    lines = [x for x in (note, INVALID_NOTE if flagged else None) if x]
    if lines:
        ax.text(0.0, -0.18, "\n".join(lines), transform=ax.transAxes, fontsize=8, va="top")
    savefig(fig, path)


def whine_waterfall_plot(path, speeds, fundamental_hz, orders, amplitudes, *, label, title,
                         invalid=None, dynamic_range_db=60.0, power=False,
                         limit_hz=None, order_labels=None, tones=()) -> None:
    """The waterfall: every order's frequency (Hz) against the speed (rad/s), each point
    coloured by the order's level 20 log10(|a| / max |a|) (dB; ``power``: a power's,
    10 log10), the orders as grey lines (NaN amplitudes: not drawn).

    Args:
        fundamental_hz: (S,) the orders' unit (the first mesh's frequency, Hz).
        orders: (k,) orders. amplitudes: (S, k). label: the quantity and its unit.
        dynamic_range_db: the colour scale's span below the largest level.
        limit_hz: None, or the frequency above which nothing is drawn (a dashed line; the
            frequency axis ends a little above it).
        order_labels: (k,) the names written at the orders' ends (default "<order>×").
        tones: (name, order of the input speed) of lines drawn dotted beside the orders (a
            rolling bearing's tones, :func:`jaxgear.cli._bearing_report.bearing_tone_lines`),
            named in a legend.
    """
    fig, ax = new_figure((8, 5.5))
    s = np.asarray(speeds, dtype=float)
    o = np.asarray(orders, dtype=float)
    a = np.abs(np.asarray(amplitudes, dtype=float))
    f = np.asarray(fundamental_hz, dtype=float)[:, None] * o[None, :]
    top = float(np.nanmax(a)) if np.isfinite(a).any() else 0.0
    ref = top if top > 0 else 1.0
    level = (10 if power else 20) * np.log10(np.maximum(a / ref, 1e-30))
    for j in range(o.size):
        ax.plot(s, f[:, j], color="0.8", lw=0.6, zorder=0)
    S = np.broadcast_to(s[:, None], f.shape)
    size = 10 + 50 * np.clip(1 + level / dynamic_range_db, 0, 1)
    sc = ax.scatter(S.ravel(), f.ravel(), c=level.ravel(), s=size.ravel(), cmap="viridis",
                    norm=Normalize(-dynamic_range_db, 0.0), linewidths=0)
    cb = fig.colorbar(sc, ax=ax)
    cb.set_label(f"level, dB re the largest ({ref:.3g} {label.split('(')[-1].rstrip(')')})")
    flagged = invalid is not None and _shade(ax, s, invalid)
    for j in range(o.size):  # each order named at its right end
        text = f"{o[j]:g}×" if order_labels is None else order_labels[j]
        ax.annotate(text, (s[-1], f[-1, j]), xytext=(3, 0), textcoords="offset points",
                    fontsize=7, va="center", color="0.3")
    for j, (name, order) in enumerate(tones):
        ax.plot(s, order * s / (2 * np.pi), color=f"C{(j + 4) % 10}", ls=":", lw=1.0,
                label=name)
    if tones:
        ax.legend(fontsize=7, loc="upper left", title="bearing tones", title_fontsize=7)
    if limit_hz is not None:
        ax.axhline(limit_hz, color="tab:red", ls="--", lw=0.9)
        ax.annotate("band limit", (s[0], limit_hz), xytext=(2, 3), textcoords="offset points",
                    fontsize=7, color="tab:red")
        ax.set_ylim(0.0, 1.15 * limit_hz)
    ax.set_xlabel("input speed (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"{title}: {label}")
    ax.grid(True, alpha=0.3)
    if flagged:
        ax.text(0.0, -0.12, INVALID_NOTE, transform=ax.transAxes, fontsize=8, va="top")
    savefig(fig, path)


def whine_level_plot(path, speeds, levels_db, orders, overall_db=None, *, ylabel, title,
                     invalid=None, note=None, span_db=70.0, order_labels=None) -> None:
    """Each order's level (dB) against the speed, and the orders' overall level as a heavy
    line (NaN levels: not drawn, an order NaN at every speed left out of the legend; the axis
    spans ``span_db`` below the highest level).

    Args:
        speeds: (S,) input speeds (rad/s). levels_db: (S, k) of the orders ``orders`` (k,).
        overall_db: None or (S,). invalid: None or (S,) booleans (shaded, as the order plot).
        order_labels: None (each line named "order <o>") or (k,) the legend's names.
    """
    fig, ax = new_figure()
    lv = np.asarray(levels_db, dtype=float)
    for j, o in enumerate(orders):
        if np.isfinite(lv[:, j]).any():  # an order out of the band at every speed: no entry
            ax.plot(speeds, lv[:, j], "-", lw=1.3, marker=".", ms=3,
                    label=f"order {o:g}" if order_labels is None else order_labels[j])
    if overall_db is not None:
        ax.plot(speeds, overall_db, "k-", lw=2.0, label="overall")
        lv = np.column_stack([lv, overall_db])
    top = float(np.nanmax(lv)) if np.isfinite(lv).any() else 0.0
    ax.set_ylim(top - span_db, top + 5.0)
    flagged = invalid is not None and _shade(ax, speeds, invalid)
    ax.set_xlabel("input speed (rad/s)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize=8, ncol=2)
    lines = [x for x in (note, INVALID_NOTE if flagged else None) if x]
    if lines:
        ax.text(0.0, -0.18, "\n".join(lines), transform=ax.transAxes, fontsize=8, va="top")
    savefig(fig, path)
