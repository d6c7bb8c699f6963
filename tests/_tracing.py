"""The functions JAX traces inside a block, from JAX's monitoring events (one trace per compiled
function: a count of the programs a call compiles, which the persistent compilation cache does
not hide; clear JAX's in-memory caches first to count from nothing)."""

import contextlib

import jax.monitoring

TRACE_EVENT = "/jax/core/compile/jaxpr_trace_duration"


@contextlib.contextmanager
def traced():
    """The names of the functions JAX traces inside the block (a list, filled as it runs)."""
    names = []

    def listen(event, duration, **kwargs):
        if event == TRACE_EVENT:
            names.append(kwargs.get("fun_name", "?"))

    jax.monitoring.register_event_duration_secs_listener(listen)
    try:
        yield names
    finally:
        jax.monitoring.unregister_event_duration_listener(listen)
