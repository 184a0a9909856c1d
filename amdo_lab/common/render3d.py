"""Off-screen 3-D figures: pyvista through EGL when it works, a matplotlib 3-D plot otherwise.

VTK crashes the whole process (a segfault, not an exception) on a machine with neither EGL nor
OSMesa, so :func:`probe_3d_rendering` first renders a sphere in a *subprocess*. Scenes are
described by plain numpy data (:class:`Mesh`, :class:`PointCloud`) and always come back as a
matplotlib figure holding a static image, so notebooks, ``savefig`` and the HTML book treat 2-D
and 3-D figures alike.
"""

from __future__ import annotations

import functools
import os
import subprocess
import sys
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from amdo_lab.common.validation import as_finite_array, check_in_range, check_sequence_of

__all__ = [
    "DISABLE_3D_VARIABLE",
    "Mesh",
    "PointCloud",
    "isosurface",
    "probe_3d_rendering",
    "render_scene",
]

#: Set this variable to 1 to force the matplotlib fallback (e.g. to compare the two).
DISABLE_3D_VARIABLE = "AMDO_DISABLE_3D"

_PROBE_SCRIPT = """
import os
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
import pyvista
plotter = pyvista.Plotter(off_screen=True, window_size=(64, 64))
plotter.add_mesh(pyvista.Sphere())
image = plotter.screenshot(return_img=True)
plotter.close()
assert image.shape[0] == 64 and image.std() > 0
print("ok")
"""


@dataclass(frozen=True)
class Mesh:
    """A triangle mesh: ``vertices`` (n, 3) and ``faces`` (m, 3) vertex indices."""

    vertices: np.ndarray
    faces: np.ndarray
    color: str = "#56B4E9"
    opacity: float = 1.0
    label: str | None = None


@dataclass(frozen=True)
class PointCloud:
    """Points (n, 3) drawn as spheres/dots of one colour."""

    points: np.ndarray
    color: str = "#D55E00"
    size: float = 6.0
    label: str | None = None


@dataclass(frozen=True)
class _ProbeResult:
    ok: bool
    detail: str = field(default="")


@functools.lru_cache(maxsize=1)
def probe_3d_rendering(timeout: float = 60.0) -> _ProbeResult:
    """Render a sphere off-screen in a subprocess; report whether pyvista works here.

    The result is cached for the life of the process. Setting ``AMDO_DISABLE_3D=1`` makes the
    probe report failure without trying.
    """
    if os.environ.get(DISABLE_3D_VARIABLE) == "1":
        return _ProbeResult(False, f"{DISABLE_3D_VARIABLE}=1 is set")
    env = dict(os.environ)
    env.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    try:
        completed = subprocess.run(
            [sys.executable, "-c", _PROBE_SCRIPT],
            capture_output=True,
            text=True,
            timeout=timeout,
            env=env,
        )
    except subprocess.TimeoutExpired:
        return _ProbeResult(False, f"the 3-D probe did not finish within {timeout:.0f} s")
    if completed.returncode == 0 and completed.stdout.strip().endswith("ok"):
        return _ProbeResult(True, "pyvista renders off-screen through EGL")
    tail = (completed.stderr or completed.stdout).strip().splitlines()[-1:] or ["no output"]
    return _ProbeResult(False, f"exit code {completed.returncode}: {tail[0]}")


def isosurface(
    field_values: np.ndarray,
    level: float,
    *,
    origin: Sequence[float] = (0.0, 0.0, 0.0),
    spacing: Sequence[float] = (1.0, 1.0, 1.0),
    color: str = "#56B4E9",
    opacity: float = 1.0,
    label: str | None = None,
) -> Mesh:
    """Marching-cubes contour ``field == level`` of a scalar field sampled on a regular grid.

    Parameters
    ----------
    field_values : (nx, ny, nz) array
        Field samples; axis ``i`` runs along world axis ``i``.
    level : float
        Iso-value, strictly between the field's minimum and maximum.
    origin, spacing : 3 floats
        World position of sample ``[0, 0, 0]`` and the grid step along each axis.
    """
    from skimage.measure import marching_cubes

    values = as_finite_array(field_values, "field_values", ndim=3)
    level = check_in_range(level, "level", values.min(), values.max())  # strictly inside the field's range
    vertices, faces, _, _ = marching_cubes(values, level=level, spacing=tuple(spacing))
    return Mesh(vertices + np.asarray(origin, dtype=float), faces, color, opacity, label)


def render_scene(
    items: Sequence[Mesh | PointCloud],
    *,
    title: str | None = None,
    view: tuple[float, float] = (20.0, -60.0),
    window_size: tuple[int, int] = (800, 600),
    figsize: tuple[float, float] = (6.4, 4.8),
) -> Figure:
    """Draw meshes and point clouds off-screen and return a matplotlib figure.

    With working off-screen VTK (see :func:`probe_3d_rendering`) the scene is rendered by pyvista
    and shown as a static image; otherwise, with one warning, by matplotlib's 3-D axes.

    Parameters
    ----------
    items : sequence of Mesh or PointCloud
        What to draw.
    title : str, optional
        Figure title.
    view : (elevation, azimuth)
        Camera angles in degrees, used by both back ends.
    window_size : (width, height)
        Render size in pixels for pyvista.
    figsize : (width, height)
        Matplotlib figure size in inches.
    """
    items = check_sequence_of(items, "items", (Mesh, PointCloud), what="a Mesh or PointCloud")
    probe = probe_3d_rendering()
    if probe.ok:
        image = _render_pyvista(items, view, window_size)
        fig, ax = plt.subplots(figsize=figsize)
        ax.imshow(image)
        ax.set_axis_off()
    else:
        _warn_fallback_once(probe.detail)
        fig = plt.figure(figsize=figsize)
        ax = fig.add_subplot(projection="3d")
        _render_matplotlib(ax, items, view)
    if title:
        ax.set_title(title)
    return fig


@functools.lru_cache(maxsize=1)
def _warn_fallback_once(detail: str) -> None:
    warnings.warn(
        f"3-D rendering with pyvista is unavailable ({detail}); drawing with matplotlib instead. "
        "Run `python -m amdo_lab check-env` for the fix.",
        RuntimeWarning,
        stacklevel=3,
    )


def _render_pyvista(
    items: Sequence[Mesh | PointCloud], view: tuple[float, float], window_size: tuple[int, int]
) -> np.ndarray:
    import pyvista

    plotter = pyvista.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    for item in items:
        if isinstance(item, Mesh):
            faces = np.hstack([np.full((len(item.faces), 1), 3), item.faces]).astype(np.int64)
            poly = pyvista.PolyData(np.asarray(item.vertices, dtype=float), faces.ravel())
            plotter.add_mesh(poly, color=item.color, opacity=item.opacity, smooth_shading=True)
        else:
            plotter.add_points(
                np.asarray(item.points, dtype=float),
                color=item.color,
                point_size=item.size,
                render_points_as_spheres=True,
            )
    plotter.view_isometric()
    elevation, azimuth = view
    plotter.camera.elevation = elevation
    plotter.camera.azimuth = azimuth + 60.0  # matplotlib's default azimuth is -60 degrees
    plotter.reset_camera()
    plotter.camera.zoom(1.3)
    image = plotter.screenshot(return_img=True)
    plotter.close()
    return image


def _render_matplotlib(ax, items: Sequence[Mesh | PointCloud], view: tuple[float, float]) -> None:
    everything = []
    for item in items:
        if isinstance(item, Mesh):
            ax.plot_trisurf(
                item.vertices[:, 0], item.vertices[:, 1], item.vertices[:, 2],
                triangles=item.faces, color=item.color, alpha=item.opacity, linewidth=0,
            )
            everything.append(item.vertices)
        else:
            ax.scatter(*np.asarray(item.points).T, color=item.color, s=item.size)
            everything.append(item.points)
    stacked = np.vstack(everything)
    centre = (stacked.max(axis=0) + stacked.min(axis=0)) / 2
    half = (stacked.max(axis=0) - stacked.min(axis=0)).max() / 2
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.view_init(elev=view[0], azim=view[1])
