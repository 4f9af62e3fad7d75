"""Process pools that stop when asked: one way to end a ``concurrent.futures`` process pool at
once, for the sweep's points and the figures' workers."""

from __future__ import annotations

import contextlib
import logging

log = logging.getLogger(__name__)

__all__ = ["stop_pool"]


def stop_pool(executor, *, grace_s: float = 2.0, what: str = "pool") -> None:
    """End an own process pool now: cancel the tasks not started, SIGTERM every worker
    (``shutdown(cancel_futures=True)`` alone would let the running tasks finish), SIGKILL
    the ones still there after ``grace_s``, and wait for the pool's manager thread, so
    that nothing is left to wait for at exit. (Reads the pool's private ``_processes`` and
    ``_executor_manager_thread``; Python 3.14's ``terminate_workers`` does the same.)"""
    processes = list((getattr(executor, "_processes", None) or {}).values())  # before shutdown clears it
    manager = getattr(executor, "_executor_manager_thread", None)
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            proc.terminate()
    # the manager thread sees the workers die, fails the futures still running and joins the workers
    if manager is not None:
        manager.join(grace_s)
    if manager is None or manager.is_alive():
        for proc in processes:
            with contextlib.suppress(OSError, ValueError, AttributeError):
                if proc.exitcode is None:
                    proc.kill()
        if manager is not None:
            manager.join(grace_s)
    for proc in processes:  # reap them (no zombies), whether or not a manager thread did
        with contextlib.suppress(OSError, ValueError, AttributeError, AssertionError):
            proc.join(grace_s)
    left = [proc.pid for proc in processes if proc.exitcode is None and proc.is_alive()]
    if left:
        log.warning("%s: worker process(es) %s did not stop", what, ", ".join(map(str, left)))
