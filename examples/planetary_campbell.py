"""Campbell diagram and mode types of the planetary stage of the user guide.

Lin & Parker's (1999, Table 1) four-planet stage with its carrier held by a torsional stiffness,
planar model (`jaxgear.planetary.PlanarPlanetary`, 21 coordinates): the natural frequencies in the
carrier frame against the carrier speed (`jaxgear.planetary.campbell`, Coriolis and centripetal
terms), each frequency at rest marked with its type (`jaxgear.planetary.classify_modes`: rotational,
translational pair, planet mode), and the shape of the lowest mode of each type. A translational
pair, one frequency at rest, splits with the speed. Writes docs/bench/planetary_campbell.png. Run
from the repository root: ``python examples/planetary_campbell.py``.
"""

import pathlib

import jax

jax.config.update("jax_enable_x64", True)  # float64 (examples switch it on)

import equinox as eqx  # noqa: E402
import matplotlib  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.use("Agg")  # files only
import matplotlib.pyplot as plt  # noqa: E402

import jaxgear as jg  # noqa: E402
import jaxgear.planetary as jp  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
COLOURS = {"rotational": "C0", "translational": "C3", "planet": "C2", "mixed": "C7"}


def stage() -> jp.PlanetaryStage:
    """The guide's stage: Lin & Parker's Table 1, four planets, the carrier held (N m/rad)."""
    lumped = jp.PlanetaryMember.lumped  # (mass kg, I/r² kg, base radius m, bearing N/m, k_u N/m)
    free = jp.PlanetaryStage.equally_spaced(
        4,
        sun=lumped(0.4, 0.39, 0.0387, 1e8),
        ring=lumped(2.35, 3.0, 0.1375, 1e8, 1e9),
        carrier=lumped(5.43, 6.29, 0.0884, 1e8),
        planet=lumped(0.66, 0.61, 0.05015, 1e8),
        sun_pressure_angle=np.radians(24.6),
        ring_pressure_angle=np.radians(24.6),
        sun_mesh_stiffness=5e8,
        ring_mesh_stiffness=5e8,
    )
    return eqx.tree_at(lambda s: s.carrier.torsional_stiffness, free, 1e8 * 0.0884**2)


def draw_shape(ax, held: jp.PlanetaryStage, shape: np.ndarray, title: str) -> None:
    """The sun, ring and planets at rest (grey) and displaced by the mode shape (black): centres
    moved by their translations, the mark of each member turned by u/r; the largest motion drawn
    as a quarter of the sun's radius. The carrier is shown by its circle of planet centres at
    rest (dotted)."""
    r_c = float(held.carrier.base_radius)
    psi = np.asarray(held.planet_angles)
    q = shape.reshape(-1, 3)  # rows: carrier, ring, sun, planets; (x or ζ, y or η, u)
    members = [(0.0, 0.0, float(held.ring.base_radius), q[1], None)]
    members += [(0.0, 0.0, float(held.sun.base_radius), q[2], None)]
    members += [
        (r_c * np.cos(p), r_c * np.sin(p), float(held.planet.base_radius), q[3 + n], p)
        for n, p in enumerate(psi)
    ]
    moves = [np.hypot(*m[3][:2]) for m in members] + [abs(m[3][2]) for m in members]
    scale = 0.25 * float(held.sun.base_radius) / max(max(moves), 1e-30)
    t = np.linspace(0.0, 2 * np.pi, 120)
    for x0, y0, r, (a, b, u), p in members:
        # a planet's (ζ, η) are radial and tangential at its angle ψ; a central member's (x, y)
        dx, dy = (
            (a, b) if p is None else (a * np.cos(p) - b * np.sin(p), a * np.sin(p) + b * np.cos(p))
        )
        x1, y1, turn = x0 + scale * dx, y0 + scale * dy, scale * u / r
        mark = np.pi / 4 if p is None else p + np.pi  # between the planets; a planet's: inwards
        inner = 0.8 if r > r_c else 0.0  # the ring's mark: a tick on its circle
        ax.plot(x0 + r * np.cos(t), y0 + r * np.sin(t), color="0.8", lw=0.8)
        ax.plot(x1 + r * np.cos(t), y1 + r * np.sin(t), color="k", lw=1.0)
        ax.plot(
            x1 + np.array([inner, 1.0]) * r * np.cos(mark + turn),
            y1 + np.array([inner, 1.0]) * r * np.sin(mark + turn),
            "k-",
            lw=1.0,
        )
    ax.plot(r_c * np.cos(t), r_c * np.sin(t), color="0.6", lw=0.8, ls=":")  # planet-centre circle
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(title, fontsize=10)


def main(out_dir=DOCS, speed_max: float = 3000.0, n_speeds: int = 61, f_max: float = 3000.0):
    """Compute the modes, types and Campbell frequencies; draw them into
    ``out_dir/planetary_campbell.png`` (None: no figure). Returns the values drawn."""
    held = stage()
    model = jp.PlanarPlanetary()
    modes = jp.planetary_modes(model, held)
    types = jp.classify_modes(modes, model, held)
    f0 = np.asarray(modes.frequencies)
    speeds = np.linspace(0.0, speed_max, n_speeds)  # carrier speed (rad/s)
    f = np.asarray(jp.campbell(model, held, speeds))  # (n_speeds, 21) Hz, ascending
    out = {"speeds": speeds, "campbell": f, "frequencies": f0, "types": types}
    if out_dir is None:
        return out
    # narrow and tall: readable at the width of a documentation page
    fig = plt.figure(figsize=(8.5, 8.0), layout="constrained")
    grid = fig.add_gridspec(2, 3, height_ratios=(1.45, 1))
    ax = fig.add_subplot(grid[0, :])
    shown = f0 < f_max
    ax.plot(speeds, np.where(f < f_max, f, np.nan), "k.", ms=2)
    seen = set()
    for fj, (kind, mult) in zip(f0[shown], types):
        name = kind.value
        label = None if name in seen else f"{name} (multiplicity {mult})"
        seen.add(name)
        ax.plot(0.0, fj, "o", ms=7, color=COLOURS[name], mec="k", mew=0.5, label=label, zorder=3)
    ax.set_xlim(-0.02 * speed_max, speed_max)
    ax.set_ylim(0.0, 1.18 * f_max)  # room for the key above the branches
    ax.set_xlabel("carrier speed Ω (rad/s)")
    ax.set_ylabel("natural frequency in the carrier frame (Hz)")
    ax.set_title("Campbell diagram, planar model, carrier held", fontsize=11)
    ax.grid(alpha=0.3)
    ax.legend(
        title="type of each frequency at rest (dots at Ω = 0)",
        fontsize=9,
        loc="upper center",
        ncols=3,
    )
    shapes = np.asarray(modes.shapes)
    for k, name in enumerate(("rotational", "translational", "planet")):
        j = next(i for i, (kind, _) in enumerate(types) if kind.value == name)
        draw_shape(fig.add_subplot(grid[1, k]), held, shapes[:, j], f"{name}, {f0[j]:.0f} Hz")
    fig.suptitle(
        "Lin & Parker's four-planet stage: frequencies against carrier speed;\n"
        "below, the lowest mode of each type (grey: at rest)",
        fontsize=11,
    )
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_dir / "planetary_campbell.png", dpi=110)
    plt.close(fig)
    return out


if __name__ == "__main__":
    main()
