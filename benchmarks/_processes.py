"""Local processes joined by ``jax.distributed`` on the loopback address: a free coordinator
port and a runner that starts one process per command line, waits for all of them and reports
the first that failed (``jaxgear bench robust`` and the two-process tests use it)."""

from __future__ import annotations

import socket
import subprocess

__all__ = ["free_port", "run_processes"]


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now (for the ``jax.distributed`` coordinator)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_processes(argvs: list[list[str]], *, env: dict, cwd, timeout: float) -> None:
    """Run one process per command line in ``argvs`` at once (their stdout discarded), in
    ``cwd`` with the environment ``env``, and wait for all of them, each within ``timeout``
    seconds.

    Raises:
        RuntimeError: a process exited non-zero (its index, exit status and the last lines of
            its stderr) or ran past ``timeout`` (the others are then stopped too).
    """
    procs = [
        subprocess.Popen(
            argv, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
        )
        for argv in argvs
    ]
    try:
        for i, p in enumerate(procs):
            try:
                _, err = p.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                raise RuntimeError(
                    f"process {i} of {len(procs)} ran past {timeout:g} s: stopped"
                ) from None
            if p.returncode != 0:
                tail = "\n".join(err.strip().splitlines()[-20:])
                raise RuntimeError(
                    f"process {i} of {len(procs)} failed (exit status {p.returncode}): {tail}"
                )
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
            p.wait()
            if not p.stderr.closed:
                p.stderr.close()
