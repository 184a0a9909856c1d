"""Chapter 0, the introduction: its exercises live in :mod:`amdo_lab.introduction.exercises`.

The chapter itself uses only the shared helpers of :mod:`amdo_lab.common`; this subpackage holds
what its exercise checks need, out of the reader's sight.
"""

from amdo_lab.introduction.exercises import simulated_rms

__all__ = ["simulated_rms"]
