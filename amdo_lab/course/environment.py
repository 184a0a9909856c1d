"""``python -m amdo_lab check-env``: is this machine ready to run and build the workbook?"""

from __future__ import annotations

import ctypes.util
import importlib.metadata
import importlib.util
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass

from amdo_lab.common.render3d import probe_3d_rendering

__all__ = [
    "BROWSER_INSTALL_COMMAND", "EGL_INSTALL_COMMAND", "REQUIRED_MODULES", "Browser",
    "EnvironmentReport", "check_environment", "find_browser",
]

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
    ("nbval", "nbval"),
    ("tqdm", "tqdm"),
    ("sphinx", "sphinx"),
    ("myst_nb", "myst-nb"),
    ("sphinx_book_theme", "sphinx-book-theme"),
    ("sphinx_copybutton", "sphinx-copybutton"),
    ("sphinx_togglebutton", "sphinx-togglebutton"),
    ("sphinx-mathjax-offline", "sphinx-mathjax-offline"),
    ("selenium", "selenium"),
    ("nbgrader", "nbgrader"),
)

EGL_INSTALL_COMMAND = "sudo apt-get update && sudo apt-get install -y libegl1 libegl-mesa0"
BROWSER_INSTALL_COMMAND = "sudo apt-get update && sudo apt-get install -y chromium chromium-driver"
BROWSER_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
DRIVER_NAMES = ("chromedriver",)


@dataclass(frozen=True)
class Browser:
    """The headless browser the book's browser test drives (None fields: not found)."""

    binary: str | None
    driver: str | None
    version: str

    @property
    def ok(self) -> bool:
        return self.binary is not None and self.driver is not None


def find_browser() -> Browser:
    """Find Chromium (or Chrome) and chromedriver on the PATH, with the browser's version."""
    binary = next((path for path in map(shutil.which, BROWSER_NAMES) if path), None)
    driver = next((path for path in map(shutil.which, DRIVER_NAMES) if path), None)
    version = ""
    if binary is not None:
        try:
            completed = subprocess.run([binary, "--version"], capture_output=True, text=True, timeout=30)
            found = re.search(r"\d+(\.\d+)+", completed.stdout)
            version = found.group(0) if found else ""
        except (OSError, subprocess.SubprocessError):
            version = ""
    return Browser(binary, driver, version)


@dataclass(frozen=True)
class EnvironmentReport:
    lines: tuple[str, ...]
    ok: bool
    rendering_3d: bool


def check_environment(probe_3d: bool = True) -> EnvironmentReport:
    """Check Python, the required packages, EGL, the browser and off-screen 3-D rendering."""
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
    browser = find_browser()
    if browser.ok:
        name = os.path.basename(browser.binary)
        lines.append(f"[ok] browser for the book's test: {name} {browser.version} with chromedriver")
    else:
        missing = " and ".join(
            what for what, path in (("Chromium", browser.binary), ("chromedriver", browser.driver))
            if path is None
        )
        lines.append(f"[warn] {missing} missing: the book's browser test is skipped; install with: "
                     f"{BROWSER_INSTALL_COMMAND}")
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
