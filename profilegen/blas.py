"""BLAS on one thread inside a block: the package's linear algebra works on matrices of a few
hundred rows (banded factors, Lemke tableaux, condensed blocks), too small for BLAS threads to
pay, and with another process on the machine OpenBLAS's spinning threads made a factorisation
~8× slower (10.8 s against 1.3 s measured on the contact build).

:func:`one_blas_thread` keeps one ``threadpoolctl`` controller for the process: each
``threadpool_limits`` call scans the loaded libraries anew (8 ms; 144 calls took 1.2 s of a
toothed-rim solve). The controller is made at the first call, after importing scipy.linalg so
that scipy's own BLAS (its wheels bundle one beside numpy's) is among the libraries it limits.
"""

from __future__ import annotations

import contextlib

_CONTROLLER: list = []


def one_blas_thread(on: bool = True):
    """A context manager: BLAS limited to one thread inside the block when ``on``."""
    if not on:
        return contextlib.nullcontext()
    if not _CONTROLLER:
        import scipy.linalg  # noqa: F401  (loads scipy's BLAS before the scan)
        from threadpoolctl import ThreadpoolController

        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0].limit(limits=1, user_api="blas")


def forget_blas_controller() -> None:
    """Drop the controller (a forked worker makes its own: the parent's describes the parent's
    thread pools)."""
    _CONTROLLER.clear()
