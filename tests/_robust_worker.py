"""One process of the multi-process Monte Carlo test (tests/test_robust.py): joins
``jax.distributed`` on the loopback address when asked, evaluates the realisations with
:func:`jaxgear.robust_samples` and saves them (every process receives every realisation).

Usage: python tests/_robust_worker.py PROCESS_ID NUM_PROCESSES PORT OUT.npz SAMPLES
"""

import sys

import jax

jax.config.update("jax_enable_x64", True)


def main():
    pid, n, port, out, samples = sys.argv[1:6]
    if int(n) > 1:
        jax.distributed.initialize(
            coordinator_address=f"127.0.0.1:{port}", num_processes=int(n), process_id=int(pid)
        )
    import numpy as np

    import jaxgear as jg
    import jaxgear.io as jio

    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=4)
    theta = jg.mesh_positions(mesh, 4, case.pair.pinion.teeth)  # one pinion revolution
    sampler = jg.DeviationSampler.for_grade(case.pair, 6)
    problem = jg.QuasiStaticMetrics(mesh, None, jax.numpy.asarray(case.torque), theta)
    r = jg.robust_samples(problem, sampler, jax.random.key(3), int(samples), batch_size=2)
    np.savez(
        out,
        te_rms=r.te_rms,
        te_ptp=r.te_ptp,
        max_line_load=r.max_line_load,
        result=r.result,
        devices=jax.device_count(),
        processes=jax.process_count(),
    )


if __name__ == "__main__":
    main()
