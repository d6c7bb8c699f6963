"""The dynamic factors of ``nrel-5mw-planetary`` (unmodified spur meshes, the case's default
contact beyond the theoretical path) at a few carrier speeds, the figures of
docs/extended-contact.md's "Measured against the line-of-action approximation".

The case's own dynamic model (``jaxgear.io.build_dynamic_model``), one
``jaxgear.dynamics.speed_sweep`` with its default settings (Newmark, automatic steps, the
settled window), printed: its first elastic mode (Hz, the mesh-averaged modes), then per carrier
speed (rad/s) its mesh frequency (Hz), the largest dynamic factor of the sun and of the ring
meshes (over the planets), the dynamic K_gamma and the run's result code (0: converged).

From the repository root: ``python -m benchmarks.extended_contact_planetary [SPEED ...]``
(default 0.05 0.25 1.10 rad/s; a few minutes on a 2-core CPU).
"""

from __future__ import annotations

import argparse
import time

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxgear.dynamics as jd  # noqa: E402
from jaxgear import io as jio  # noqa: E402

CASE = "nrel-5mw-planetary"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("speeds", nargs="*", type=float, default=[0.05, 0.25, 1.10],
                    help="carrier speeds (rad/s)")
    args = ap.parse_args(argv)
    model, _ = jio.build_dynamic_model(jio.load_case(CASE))
    modes = jd.mesh_averaged_modes(model)
    f1 = float(np.asarray(modes.frequency)[~np.asarray(modes.rigid)][0])
    print(f"{CASE}: first elastic mode {f1:.2f} Hz")
    speeds = np.asarray(args.speeds, dtype=float)
    t0 = time.perf_counter()
    r = jd.speed_sweep(model, speeds)
    seconds = time.perf_counter() - t0
    sun, ring = (np.asarray(d).max(-1) for d in r.results.dynamic_factors)
    k_gamma = np.asarray(r.results.k_gamma)
    codes = np.asarray(r.results.result).reshape(len(speeds), -1).max(-1)
    f_mesh = speeds / float(model.mesh_period_angle())
    print("speed (rad/s)  mesh (Hz)   DF sun  DF ring  K_gamma  result")
    for row in zip(speeds, f_mesh, sun, ring, k_gamma, codes, strict=True):
        print("{:13.4f} {:10.3f} {:8.5f} {:8.5f} {:8.5f} {:7d}".format(*row))
    print(f"({seconds:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
