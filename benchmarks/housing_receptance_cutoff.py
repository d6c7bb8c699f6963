"""The housing's receptance in the band against the cut-off (docs/fem_prep.md,
"Receptance in the band against the cut-off"), measured:

The box housing of tests/test_housing.py (0.3 x 0.2 x 0.2 m, 8 mm walls, three bores, four feet;
Tet10) in 100 mm and 50 mm cells, the band 0 .. 2 kHz, a structural loss factor of 0.02 on both
models (``K (1 + i eta)``: ``CondensedHousing.receptance`` and ``PreparedHousing.full_receptance``).
For cut-offs of 1.5, 2, 3, 4, 6, 8 and 10 x the band's top: the matrix-norm (Frobenius) relative
error of the seats' receptance ``|H_cb - H_full| / |H_full|`` per frequency (a grid of ``step``
Hz and, about each free-seat resonance f_r in the band, f_r (1 + k eta / 4) for k = -2 .. 2),
its largest value and median, and the free-seat resonances' relative errors.

Writes docs/bench/housing_receptance_cutoff.json. From the repository root:
``python -m benchmarks.housing_receptance_cutoff`` (about 10 min of CPU).
"""

from __future__ import annotations

import json
import pathlib
import time

import numpy as np

import fem_prep
from fem_prep.housing import Bore, Foot, HousingBox, mesh_box, prepare_housing

ROOT = pathlib.Path(__file__).resolve().parents[1]
STEEL = fem_prep.Material(210e9, 0.3, 7800.0)
ETA = 0.02
BAND_HZ = 2000.0
MULTIPLES = (1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0)
FEET = (
    Foot((0.0, 0.05), (0.0, 0.05)),
    Foot((0.25, 0.3), (0.0, 0.05)),
    Foot((0.0, 0.05), (0.15, 0.2)),
    Foot((0.25, 0.3), (0.15, 0.2)),
)
BORES = (
    Bore("y-", (0.1, 0.12), 0.03),
    Bore("y+", (0.1, 0.12), 0.03),
    Bore("y-", (0.21, 0.12), 0.025),
)


def sweep(size: float, step: float) -> dict:
    hm = mesh_box(HousingBox(0.3, 0.2, 0.2, 0.008, bores=BORES, feet=FEET), size)
    ref = prepare_housing(hm, STEEL, MULTIPLES[0] * BAND_HZ)
    ff = ref.full_modes(12)[0]
    fr = ff[ff <= BAND_HZ]
    f = np.unique(
        np.r_[
            np.arange(0.0, BAND_HZ + 1e-9, step),
            np.outer(fr, 1 + ETA / 4 * np.arange(-2, 3)).ravel(),
        ]
    )
    f = f[f <= BAND_HZ]
    t0 = time.perf_counter()
    Hf = ref.full_receptance(f, loss_factor=ETA)
    full_s = time.perf_counter() - t0
    rows = []
    for m in MULTIPLES:
        p = ref if m == MULTIPLES[0] else prepare_housing(hm, STEEL, m * BAND_HZ)
        ch = p.condensed_housing()
        e = np.linalg.norm(ch.receptance(f, loss_factor=ETA) - Hf, axis=(1, 2))
        e /= np.linalg.norm(Hf, axis=(1, 2))
        d = ch.modes(fr.size)[0] / fr - 1
        rows.append(
            {
                "multiple": m,
                "cutoff_hz": m * BAND_HZ,
                "interior_modes": int(p.condensed.n_modes),
                "max_error": float(e.max()),
                "max_error_at_hz": float(f[np.argmax(e)]),
                "median_error": float(np.median(e)),
                "resonance_errors": d.tolist(),
                "errors": e.tolist(),
            }
        )
        print(
            f"{size} m x{m}: {rows[-1]['interior_modes']} modes, largest {e.max():.4g} "
            f"median {np.median(e):.4g}, resonances {100 * d.min():.4f}..{100 * d.max():.4f} %",
            flush=True,
        )
    return {
        "cell_m": size,
        "dofs": int(ref.K.shape[0]),
        "resonances_hz": fr.tolist(),
        "frequencies_hz": f.tolist(),
        "full_receptance_s": full_s,
        "cutoffs": rows,
    }


def main() -> None:
    out = {
        "loss_factor": ETA,
        "band_hz": BAND_HZ,
        "boxes": [sweep(0.1, 25.0), sweep(0.05, 100.0)],
    }
    path = ROOT / "docs" / "bench" / "housing_receptance_cutoff.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(path)


if __name__ == "__main__":
    main()
