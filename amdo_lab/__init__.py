"""AMDO Lab: a teaching workbook on articulated and deformable objects.

Importing the package selects VTK's EGL render window *before* pyvista can be imported, so 3-D
figures render off-screen with no X server (and VTK's X-server warning stays out of notebooks).
A value the user set already is respected.
"""

from __future__ import annotations

import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

__version__ = "0.1.0"

from amdo_lab.common.rng import make_rng  # noqa: E402  (after the environment is set)

__all__ = ["__version__", "make_rng"]
