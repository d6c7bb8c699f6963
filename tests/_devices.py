"""Shared by the sharded-sweep tests: a script run in a separate process on forced CPU devices
(the device count is fixed when JAX starts, so it cannot change inside the test process)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_on_cpu_devices(script: str, devices: int = 4, timeout: float = 600) -> str:
    """Run the Python ``script`` with ``devices`` forced CPU devices from the repository root
    (at most ``timeout`` s); asserts it exits with 0 (showing the end of its stderr otherwise) and returns its stdout."""
    env = dict(
        os.environ,
        # the inherited flags (the suite's XLA level, tests/conftest.py) and the device count
        XLA_FLAGS=f"{os.environ.get('XLA_FLAGS', '')} --xla_force_host_platform_device_count={devices}",
        JAX_PLATFORMS="cpu",
    )
    r = subprocess.run(
        [sys.executable, "-c", script],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    return r.stdout
