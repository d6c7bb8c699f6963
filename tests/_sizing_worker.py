"""One process of the sizing's device and process tests (tests/test_sizing_scale.py): runs
``jaxgear size`` from this source tree, as process PROCESS_ID of NUM_PROCESSES joined by
``jax.distributed`` on the loopback address when NUM_PROCESSES > 1 (process 0 writes OUT).

Usage: python tests/_sizing_worker.py SPEC OUT CHUNK [PROCESS_ID NUM_PROCESSES PORT]
"""

import sys


def main() -> int:
    spec, out, chunk, *dist = sys.argv[1:]
    argv = ["size", spec, "--out", out, "--chunk", chunk, "--quiet"]
    if dist:
        pid, n, port = dist
        argv += ["--coordinator-address", f"127.0.0.1:{port}", "--num-processes", n,
                 "--process-id", pid]
    from jaxgear.cli import main as cli

    return cli(argv)


if __name__ == "__main__":
    sys.exit(main())
