"""Which OpenBLAS kernel runs here, and which other one the notebooks are run under a second time.

OpenBLAS picks a kernel per CPU (``OPENBLAS_CORETYPE`` overrides it); kernels round differently, so a
result that depends on the kernel would differ between a student's laptop and the machine that wrote
the committed outputs. ``make test-second-kernel`` runs every notebook under the kernel this script
prints: ``Nehalem`` on x86-64 (it runs on every x86-64 CPU), ``Haswell`` where Nehalem is already the
default; ``ARMV8`` on 64-bit ARM (``NEOVERSEN1`` where ARMV8 is the default).

Run as a script it prints the second kernel's name, or the one in effect with ``--current``.
"""

from __future__ import annotations

import platform
import sys

SECOND_KERNEL = {"x86_64": ("Nehalem", "Haswell"), "AMD64": ("Nehalem", "Haswell"),
                 "aarch64": ("ARMV8", "NEOVERSEN1"), "arm64": ("ARMV8", "NEOVERSEN1")}


def current_kernel() -> str:
    """The OpenBLAS kernel numpy runs on here (``"unknown"`` if numpy does not use OpenBLAS)."""
    import numpy  # noqa: F401 - loads the BLAS that threadpoolctl inspects
    from threadpoolctl import threadpool_info

    for library in threadpool_info():
        if library.get("internal_api") == "openblas":
            return str(library.get("architecture") or "unknown")
    return "unknown"


def second_kernel(current: str, machine: str | None = None) -> str:
    """A kernel other than ``current`` that runs on this CPU family."""
    first, fallback = SECOND_KERNEL.get(machine or platform.machine(), ("Nehalem", "Haswell"))
    return fallback if current.lower() == first.lower() else first


if __name__ == "__main__":
    here = current_kernel()
    print(here if "--current" in sys.argv[1:] else second_kernel(here))
