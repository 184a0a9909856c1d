"""``python -m amdo_lab check-env``: is this machine ready to run and build the workbook?"""

from __future__ import annotations

import ctypes.util
import importlib.metadata
import importlib.util
import os
import sys
from dataclasses import dataclass

from amdo_lab.common.render3d import probe_3d_rendering

__all__ = ["EGL_INSTALL_COMMAND", "REQUIRED_MODULES", "EnvironmentReport", "check_environment"]

#: Module name and the pip requirement that provides it.
REQUIRED_MODULES: tuple[tuple[str, str], ...] = (
    ("numpy", "numpy"),
    ("scipy", "scipy"),
    ("matplotlib", "matplotlib"),
    ("pandas", "pandas"),
    ("cv2", "opencv-python-headless"),
    ("sklearn", "scikit-learn"),
    ("skimage", "scikit-image"),
    ("dipy", "dipy"),
    ("statsmodels", "statsmodels"),
    ("pyvista", "pyvista"),
    ("vtk", "vtk"),
    ("nbclient", "nbclient"),
    ("nbconvert", "nbconvert"),
    ("nbval", "nbval"),
    ("jupyter_server_mathjax", "jupyter-server-mathjax"),
    ("tqdm", "tqdm"),
)

EGL_INSTALL_COMMAND = "sudo apt-get update && sudo apt-get install -y libegl1 libegl-mesa0"


@dataclass(frozen=True)
class EnvironmentReport:
    lines: tuple[str, ...]
    ok: bool
    rendering_3d: bool


def check_environment(probe_3d: bool = True) -> EnvironmentReport:
    """Check Python, the required packages, EGL and off-screen 3-D rendering."""
    lines = []
    ok = True
    version = sys.version_info
    python_ok = version >= (3, 11)
    ok &= python_ok
    lines.append(f"[{'ok' if python_ok else 'FAIL'}] Python {version.major}.{version.minor}.{version.micro} (3.11 or newer needed)")
    for module_name, requirement in REQUIRED_MODULES:
        # find_spec checks presence without importing: some packages (dipy) print progress-bar
        # warnings at import time, and the 3-D probe below imports VTK in a subprocess anyway.
        if importlib.util.find_spec(module_name) is None:
            ok = False
            lines.append(f"[FAIL] {requirement} is not installed; run `make book` or "
                         "`pip install -r environment.txt`")
            continue
        try:
            version_text = importlib.metadata.version(requirement)
        except importlib.metadata.PackageNotFoundError:
            version_text = "(version unknown)"
        lines.append(f"[ok] {requirement} {version_text}")
    egl = ctypes.util.find_library("EGL")
    lines.append(
        f"[{'ok' if egl else 'warn'}] EGL library: {egl or 'missing; install it with: ' + EGL_INSTALL_COMMAND}"
    )
    lines.append(f"[ok] VTK_DEFAULT_OPENGL_WINDOW={os.environ.get('VTK_DEFAULT_OPENGL_WINDOW', '(unset)')}")
    rendering = False
    if probe_3d:
        probe = probe_3d_rendering()
        rendering = probe.ok
        if probe.ok:
            lines.append(f"[ok] 3-D rendering: {probe.detail}")
        else:
            lines.append(
                f"[warn] 3-D rendering unavailable ({probe.detail}); 3-D figures fall back to "
                f"matplotlib. Fix: {EGL_INSTALL_COMMAND}"
            )
    return EnvironmentReport(tuple(lines), ok, rendering)
