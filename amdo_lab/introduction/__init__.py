"""Chapter 0, the introduction: its exercises live in :mod:`amdo_lab.introduction.exercises`.

The chapter itself uses only the shared helpers of :mod:`amdo_lab.common`; this subpackage holds
what its exercise checks need and nothing that computes an answer.
"""

from amdo_lab.introduction.exercises import scale_case

__all__ = ["scale_case"]
