"""Joining ``jax.distributed`` for the commands that run on several processes (``jaxgear
robust``, ``jaxgear size``): their ``--coordinator-address``, ``--num-processes`` and
``--process-id`` (checked together by :mod:`jaxgear.cli._options`)."""

from __future__ import annotations

import jax

__all__ = ["join_processes"]


def join_processes(args) -> None:
    """Join ``jax.distributed`` as process ``args.process_id`` of ``args.num_processes`` (the
    coordinator at ``args.coordinator_address``, HOST:PORT, process 0's host); nothing for one
    process (None or 1). Called before any other JAX work of the command."""
    if args.num_processes is not None and args.num_processes > 1:
        jax.distributed.initialize(coordinator_address=args.coordinator_address,
                                   num_processes=args.num_processes, process_id=args.process_id)
