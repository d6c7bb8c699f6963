"""The example scripts that draw the documentation's figures run and show what their pages say.

examples/planetary_campbell.py (the Campbell diagram of docs/guide/planetary.md): Lin & Parker's
(1999) theorem for N equally spaced identical planets in the planar model, 3 (3 + N) coordinates,
gives 6 rotational frequencies (multiplicity 1), 6 translational pairs and 3 planet-mode
frequencies of multiplicity N − 3; at rest the Campbell frequencies are the natural frequencies,
and the lowest translational pair, one frequency at rest, splits with the carrier speed (the
sentence of the guide page). A few seconds."""

from __future__ import annotations

import collections

import numpy as np
from _examples import load_example


def test_planetary_campbell_example(tmp_path):
    example = load_example("planetary_campbell")
    out = example.main(tmp_path, speed_max=1000.0, n_speeds=5)
    png = (tmp_path / "planetary_campbell.png").read_bytes()
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and len(png) > 20_000

    n = 4  # planets
    f0, types, f = out["frequencies"], out["types"], out["campbell"]
    assert f0.shape == (3 * (3 + n),) and f.shape == (5, 3 * (3 + n))
    count = collections.Counter((kind.value, mult) for kind, mult in types)
    assert count == {("rotational", 1): 6, ("translational", 2): 12, ("planet", n - 3): 3}
    np.testing.assert_allclose(f[0], f0, rtol=1e-9)
    # the lowest translational pair: equal at rest, apart at speed (Coriolis)
    j = next(i for i, (kind, _) in enumerate(types) if kind.value == "translational")
    assert abs(f0[j + 1] - f0[j]) < 1e-6 * f0[j]
    branches = f[-1][np.argsort(np.abs(f[-1] - f0[j]))[:2]]  # the two that leave it
    assert np.ptp(branches) > 0.05 * f0[j], branches
