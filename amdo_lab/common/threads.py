"""One BLAS thread for small dense algebra, without re-scanning the loaded libraries on every call."""

from __future__ import annotations

import sys
from contextlib import AbstractContextManager

from threadpoolctl import ThreadpoolController

__all__ = ["one_blas_thread"]

_CONTROLLER: ThreadpoolController | None = None
_MODULES_SEEN = 0  # len(sys.modules) when the controller was built: a native library loads with a module


def one_blas_thread() -> AbstractContextManager:
    """Context manager that limits every BLAS/OpenMP pool to one thread and restores it on exit.

    ``threadpoolctl.threadpool_limits(1)`` looks up the loaded native libraries again at each call
    (it reads the process's memory map), which cost about 0.5-2 ms a call here; a tracking frame
    enters such a block twice. The libraries are looked up once, on first use, and the controller is
    kept. A library loaded after that first call is not limited, so call this only after numpy and
    scipy are imported (every caller in the package is).

    Small matrices (tens to hundreds of rows) run faster on one thread: more threads only contend,
    on a shared two-core machine many times slower.

    Returns
    -------
    contextlib.AbstractContextManager
        Use as ``with one_blas_thread(): ...``.
    """
    global _CONTROLLER, _MODULES_SEEN
    if _CONTROLLER is None or len(sys.modules) != _MODULES_SEEN:
        _CONTROLLER, _MODULES_SEEN = ThreadpoolController(), len(sys.modules)
    return _CONTROLLER.limit(limits=1)
