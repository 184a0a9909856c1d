"""Synthetic T1-like MRI slices of Iberian hams with two muscles bounded by fat septa (Caro et al. 2004, Sec. 2).

A slice is drawn in millimetres and rendered on the paper's grid: 425 rows x 522 columns of
0.20 x 0.23 mm (a field of view of 85 x 120 mm), slices 2 mm apart. Each ham has skin and
subcutaneous fat, a bone (dark cortex, bright marrow), the *biceps femoris* and the
*semimembranosus*, each bounded by a 0.7 mm bright fat septum, distractor septa in the
surrounding muscle, marbling flecks, a smooth bias field and Rician noise.

A muscle is a star-shaped solid: at height ``z`` its cross-section has the radius
``r(theta) = r0(z) (1 + sum_k a_k cos(k theta + phi_k + w_k z))`` with ``r0(z) = R sqrt(1 - z^2/L^2)``
for ``|z| <= 0.8 L``, so its area ``pi r0(z)^2 (1 + sum_k a_k^2 / 2)`` and its volume are exact.
The truth of a slice is the septum's centre line. Ripening shrinks each muscle to a volume
fraction per stage (1, 0.85, 0.65, 0.50 on average) and each ham's weight by 0, 8, 20, 30 %.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from amdo_lab.common import as_finite_array, check_choice, check_in_range, check_positive_int, make_rng

__all__ = ["IMAGE_SHAPE", "MUSCLES", "PIXEL_MM", "SLICE_MM", "STAGES", "STAGE_VOLUME_FRACTION",
           "STAGE_WEIGHT_LOSS", "HamSlice", "HamStudy", "MuscleShape", "initial_contour", "make_ham_slice",
           "make_ham_study"]

#: Rows x columns of a slice (85 x 120 mm at 0.20 x 0.23 mm per pixel).
IMAGE_SHAPE = (425, 522)
#: Pixel size along rows and columns, in mm (Sec. 2: "0.23x0.20x2 mm").
PIXEL_MM = (0.20, 0.23)
#: Distance between slices, in mm (Sec. 2).
SLICE_MM = 2.0
#: The four ripening stages of Sec. 3.2.
STAGES = ("raw", "post-salting", "semi-dry", "dry-cured")
#: The two muscles the paper segments.
MUSCLES = ("biceps femoris", "semimembranosus")
#: Mean volume fraction of a muscle per stage (our choice: the text gives "up to 50 %" at the end).
STAGE_VOLUME_FRACTION = (1.0, 0.85, 0.65, 0.50)
#: Mean weight loss of a ham per stage (our choice around the traditional "approximately 30 %").
STAGE_WEIGHT_LOSS = (0.0, 0.08, 0.20, 0.30)
#: Width of a fat septum, mm.
SEPTUM_MM = 0.7
#: Hams withdrawn for chemistry after each stage (Sec. 3.2: 15, 12, 9, 6 remain).
WITHDRAWN_PER_STAGE = 3
#: Largest number of hams a study holds.
MAX_HAMS = 1000
#: Largest height along a muscle, and largest polar angle, a :class:`MuscleShape` accepts (mm, radians).
MAX_HEIGHT_MM = MAX_ANGLE = 1e6
#: Points on a muscle's true centre line (:meth:`MuscleShape.contour_px`).
CONTOUR_POINTS = 400

_REFERENCE = ("A. Caro, P.G. Rodriguez, M.L. Duran, M.M. Avila, T. Antequera, R. Gallardo. A Comparison of "
              "Algorithm Design Paradigms in Active Contours for Muscle Recognition. AMDO 2004, LNCS 3179, "
              "pp. 249-258.")
_LAYOUT = {  # centre (row mm, col mm) on the raw ham, mean R and L in mm, interior intensity
    "biceps femoris": ((30.0, 38.0), 14.0, 36.0, 0.44),
    "semimembranosus": ((60.0, 49.0), 11.0, 30.0, 0.47),
}
_HAM_CENTRE, _HAM_AXES, _FAT_MM = (42.5, 60.0), (37.0, 56.0), 3.0
_BONE_CENTRE, _BONE_AXES = (40.0, 84.0), (7.0, 8.5)
_PIXEL_ALONG_NORMAL = float(np.mean(PIXEL_MM))


@dataclass(frozen=True)
class MuscleShape:
    """One muscle as a star-shaped solid (mm): centre, equatorial radius, half-length and shape terms.

    Parameters
    ----------
    centre_mm : (2,) ndarray
        Centre (row, column) in mm.
    radius_mm : float
        ``R``: radius of the mean cross-section at ``z = 0``.
    half_length_mm : float
        ``L``: the solid spans ``|z| <= 0.8 L``.
    coefficients : (k, 3) ndarray
        Rows ``(k, a_k, phi_k)`` of the radial harmonics.
    twist : (k,) ndarray
        ``w_k``, radians per mm: how each harmonic turns along ``z``.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 2 and 3.2 (the muscles segmented); the solid is our stand-in.
    """

    centre_mm: np.ndarray
    radius_mm: float
    half_length_mm: float
    coefficients: np.ndarray
    twist: np.ndarray

    def r0(self, z_mm: float) -> float:
        """Mean radius of the cross-section at height ``z_mm`` (0 outside the solid).

        Parameters
        ----------
        z_mm : float
            Height along the muscle, mm (0 at its middle).

        Returns
        -------
        float
            ``R sqrt(1 - z^2 / L^2)`` for ``|z| <= 0.8 L``, else 0, in mm.
        """
        z_mm = check_in_range(z_mm, "z_mm", -MAX_HEIGHT_MM, MAX_HEIGHT_MM, closed="both")
        ratio = z_mm / self.half_length_mm
        return self.radius_mm * float(np.sqrt(1.0 - ratio ** 2)) if abs(ratio) <= 0.8 else 0.0

    def radius(self, theta: np.ndarray, z_mm: float) -> tuple[np.ndarray, np.ndarray]:
        """``r(theta)`` and ``dr/dtheta`` at height ``z_mm``, in mm.

        Parameters
        ----------
        theta : ndarray
            Polar angles, radians.
        z_mm : float
            Height along the muscle, mm.

        Returns
        -------
        r, dr : ndarray
            The radius and its derivative in ``theta``, shaped as ``theta``.
        """
        theta = as_finite_array(theta, "theta", allow_empty=True, max_abs=MAX_ANGLE)
        r0 = self.r0(z_mm)
        k, a, phi = self.coefficients.T
        angle = k * theta[..., None] + phi + self.twist * z_mm
        return r0 * (1 + np.sum(a * np.cos(angle), axis=-1)), -r0 * np.sum(k * a * np.sin(angle), axis=-1)

    def area_mm2(self, z_mm: float) -> float:
        """Exact area of the cross-section (inside the septum's centre line) at ``z_mm``, mm^2.

        Parameters
        ----------
        z_mm : float
            Height along the muscle, mm.

        Returns
        -------
        float
            ``pi r0(z)^2 (1 + sum_k a_k^2 / 2)``.
        """
        return float(np.pi * self.r0(z_mm) ** 2 * (1 + 0.5 * np.sum(self.coefficients[:, 1] ** 2)))

    def volume_mm3(self) -> float:
        """Exact volume of the solid, mm^3: the integral of :meth:`area_mm2` over ``|z| <= 0.8 L``.

        Returns
        -------
        float
            The volume, mm^3.
        """
        shape = 1 + 0.5 * np.sum(self.coefficients[:, 1] ** 2)
        return float(np.pi * shape * self.radius_mm ** 2 * self.half_length_mm * (1.6 - 2 * 0.8 ** 3 / 3))

    def contour_px(self, z_mm: float) -> np.ndarray:
        """The septum's centre line at ``z_mm`` as ``(CONTOUR_POINTS, 2)`` (row, col) pixel coordinates.

        Parameters
        ----------
        z_mm : float
            Height along the muscle, mm.

        Returns
        -------
        (CONTOUR_POINTS, 2) ndarray
            The closed line, counter-clockwise in (row, col).
        """
        theta = np.linspace(0, 2 * np.pi, CONTOUR_POINTS, endpoint=False)
        r, _ = self.radius(theta, z_mm)
        rows = self.centre_mm[0] + r * np.sin(theta)
        cols = self.centre_mm[1] + r * np.cos(theta)
        return np.column_stack([rows / PIXEL_MM[0], cols / PIXEL_MM[1]])

    def _scaled(self, factor: float, centre_factor: float) -> MuscleShape:
        """The solid shrunk by ``factor`` in every direction, its centre moved towards the ham's."""
        centre = np.asarray(_HAM_CENTRE) + centre_factor * (self.centre_mm - np.asarray(_HAM_CENTRE))
        return MuscleShape(centre, self.radius_mm * factor, self.half_length_mm * factor, self.coefficients,
                           self.twist / factor)


@dataclass(frozen=True)
class HamSlice:
    """One rendered slice: the image, each muscle's true contour (px) and exact area (mm^2).

    Parameters
    ----------
    image : (425, 522) ndarray
        Intensities, about 0 (air) to 1 (fat).
    contours : dict
        Muscle name -> ``(n, 2)`` (row, col) septum centre line, for the muscles present.
    areas_mm2 : dict
        Muscle name -> exact area inside the centre line.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 2 (the images) and Fig. 1.
    """

    image: np.ndarray
    contours: dict
    areas_mm2: dict


@dataclass(frozen=True)
class _Ham:
    muscles: dict
    fat_flecks: float
    distractors: np.ndarray   # rows: centre row, centre col, radius, start angle, extent (mm, rad)


def _draw_ham(rng: np.random.Generator) -> _Ham:
    muscles = {}
    for name, (centre, radius, length, _) in _LAYOUT.items():
        k = np.array([2.0, 3.0, 4.0])
        a = rng.uniform([0.05, 0.02, 0.0], [0.11, 0.05, 0.025])
        coefficients = np.column_stack([k, a, rng.uniform(0, 2 * np.pi, 3)])
        muscles[name] = MuscleShape(np.asarray(centre) + rng.normal(0, 0.8, 2), radius * rng.uniform(0.93, 1.07),
                                    length * rng.uniform(0.93, 1.07), coefficients, rng.normal(0, 0.01, 3))
    distractors = []
    for name, shape in muscles.items():   # arcs 3-7 mm outside each muscle, and two loose ones
        for _ in range(2):
            gap = rng.uniform(3.0, 7.0)
            distractors.append([*shape.centre_mm, shape.radius_mm * 1.1 + gap, rng.uniform(0, 2 * np.pi),
                                rng.uniform(0.6, 1.2)])
    for _ in range(2):
        distractors.append([rng.uniform(25, 60), rng.uniform(55, 80), rng.uniform(8, 14),
                            rng.uniform(0, 2 * np.pi), rng.uniform(0.8, 1.6)])
    return _Ham(muscles, rng.uniform(0.8, 1.2), np.array(distractors))


def _inside(signed_mm: np.ndarray) -> np.ndarray:
    """Fraction of each pixel inside a boundary at signed distance ``signed_mm`` (negative inside)."""
    return np.clip(0.5 - signed_mm / _PIXEL_ALONG_NORMAL, 0.0, 1.0)


def _band(distance_mm: np.ndarray, width_mm: float) -> np.ndarray:
    """Fraction of each pixel covered by a band of ``width_mm`` centred at distance 0 (partial volume)."""
    return np.clip((width_mm / 2 - np.abs(distance_mm)) / _PIXEL_ALONG_NORMAL + 0.5, 0.0, 1.0)


def _render(ham: _Ham, z_mm: float, ham_scale: float, rng: np.random.Generator, noise: float) -> HamSlice:
    rows, cols = IMAGE_SHAPE
    Y = (np.arange(rows) * PIXEL_MM[0])[:, None]
    X = (np.arange(cols) * PIXEL_MM[1])[None, :]
    ay, ax = ham_scale * np.asarray(_HAM_AXES)
    q = np.sqrt(((Y - _HAM_CENTRE[0]) / ay) ** 2 + ((X - _HAM_CENTRE[1]) / ax) ** 2)
    image = 0.03 + (0.85 - 0.03) * _inside((q - 1) * min(ay, ax))                  # skin and fat
    tissue = _inside((q - 1) * min(ay, ax) + _FAT_MM)
    image += (0.50 - 0.85) * tissue                                                # muscle tissue
    bone_centre = np.asarray(_HAM_CENTRE) + ham_scale * (np.asarray(_BONE_CENTRE) - _HAM_CENTRE)
    qb = np.sqrt(((Y - bone_centre[0]) / _BONE_AXES[0]) ** 2 + ((X - bone_centre[1]) / _BONE_AXES[1]) ** 2)
    image += (0.12 - image) * _inside((qb - 1) * _BONE_AXES[0])                    # cortex
    image += (0.75 - image) * _inside((qb - 1) * _BONE_AXES[0] + 1.5)              # marrow
    contours, areas, muscle_mask = {}, {}, np.zeros(IMAGE_SHAPE)
    septa = np.zeros(IMAGE_SHAPE)
    for name, shape in ham.muscles.items():
        if shape.r0(z_mm) <= 0:
            continue
        dy, dx = Y - shape.centre_mm[0], X - shape.centre_mm[1]
        rho, theta = np.hypot(dy, dx), np.arctan2(dy, dx)
        r, dr = shape.radius(theta, z_mm)
        signed = (rho - r) / np.sqrt(1 + (dr / r) ** 2)                            # first-order distance
        inside = _inside(signed)
        image += (_LAYOUT[name][3] - image) * inside
        muscle_mask = np.maximum(muscle_mask, inside)
        septa = np.maximum(septa, _band(signed, SEPTUM_MM))
        contours[name], areas[name] = shape.contour_px(z_mm), shape.area_mm2(z_mm)
    arcs = np.zeros(IMAGE_SHAPE)
    for cy, cx, radius, start, extent in ham.distractors:
        dy, dx = Y - cy, X - cx
        along = np.mod(np.arctan2(dy, dx) - start - 0.02 * z_mm, 2 * np.pi)
        arcs = np.maximum(arcs, _band(np.hypot(dy, dx) - radius, 0.6) * (along < extent))
    image += (0.80 - image) * arcs * tissue * (1 - muscle_mask)
    image += (0.85 - image) * septa
    flecks = (rng.random(IMAGE_SHAPE) < 0.004 * ham.fat_flecks) * muscle_mask      # marbling
    image += 0.25 * ndimage.gaussian_filter(flecks.astype(float), 1.2) / 0.11
    yy, xx = (Y - 42.5) / 42.5, (X - 60.0) / 60.0
    c = rng.normal(0, 1, 3)
    image = image * (1 + 0.06 * (c[0] * yy + c[1] * xx + c[2] * yy * xx))          # bias field
    real = image + noise * rng.standard_normal(IMAGE_SHAPE)                          # Rician noise
    image = np.sqrt(real ** 2 + (noise * rng.standard_normal(IMAGE_SHAPE)) ** 2)
    return HamSlice(image, contours, areas)


def make_ham_slice(*, rng: int | np.random.Generator, scale: float = 1.0, noise: float = 0.04) -> HamSlice:
    """One mid-muscle slice of a freshly drawn ham: the test image of the chapter's toy-to-paper step.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the ham's anatomy and of the slice's noise.
    scale : float
        Linear size of the muscles against a raw ham, in (0.5, 1.2] (0.79 is a dry-cured ham).
    noise : float
        Standard deviation of each Rician component, in [0, 0.3] (intensities run from 0 to 1).

    Returns
    -------
    HamSlice
        The image, the true contours of both muscles and their exact areas.

    References
    ----------
    A. Caro et al., A Comparison of Algorithm Design Paradigms in Active Contours for Muscle
    Recognition, AMDO 2004, LNCS 3179, Sec. 2.

    Examples
    --------
    >>> ham = make_ham_slice(rng=0)
    >>> ham.image.shape, sorted(ham.areas_mm2)
    ((425, 522), ['biceps femoris', 'semimembranosus'])
    """
    generator = make_rng(rng, "rng")
    scale = check_in_range(scale, "scale", 0.5, 1.2, closed="right")
    noise = check_in_range(noise, "noise", 0.0, 0.3, closed="both")
    ham = _draw_ham(generator)
    ham = _Ham({name: shape._scaled(scale, 1.0) for name, shape in ham.muscles.items()}, ham.fat_flecks,
               ham.distractors)
    return _render(ham, 0.0, 1.0, generator, noise)


class HamStudy:
    """A seeded ripening study: hams scanned at four stages, three withdrawn after each (Sec. 3.2).

    Slices are rendered on demand (:meth:`slice`), so a study of 15 hams costs nothing until used.

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the whole study.
    n_hams : int
        Hams scanned raw, at least 12 and at most 1000; three are withdrawn after each stage
        (the paper's 15 leave 15, 12, 9 and 6).
    noise : float
        Rician noise of every slice, in [0, 0.3].

    Attributes
    ----------
    weights : (n_hams, 4) ndarray
        Weight of each ham (kg) at each stage, NaN once withdrawn.
    volume_fraction : (n_hams, 4) ndarray
        Each ham's muscle volume against its raw volume, per stage (NaN once withdrawn).

    References
    ----------
    Caro et al., AMDO 2004, Sec. 2 and 3.2.

    Examples
    --------
    >>> study = make_ham_study(rng=1, n_hams=12)
    >>> study.hams_at(3)
    [0, 1, 2]
    """

    def __init__(self, rng: int | np.random.Generator, n_hams: int = 15, noise: float = 0.04) -> None:
        generator = make_rng(rng, "rng")
        self.n_hams = check_positive_int(n_hams, "n_hams", minimum=4 * WITHDRAWN_PER_STAGE, maximum=MAX_HAMS)
        self.noise = check_in_range(noise, "noise", 0.0, 0.3, closed="both")
        self._seed = int(generator.integers(2 ** 31))
        self._hams = [_draw_ham(generator) for _ in range(self.n_hams)]
        shrink = np.asarray(STAGE_VOLUME_FRACTION) * (1 + generator.normal(0, 0.03, (self.n_hams, 4)))
        shrink[:, 0] = 1.0
        self.volume_fraction = np.minimum.accumulate(shrink, axis=1)
        loss = np.asarray(STAGE_WEIGHT_LOSS) + generator.normal(0, 0.015, (self.n_hams, 4))
        loss[:, 0] = 0.0
        self.weights = generator.uniform(8.5, 11.0, (self.n_hams, 1)) * (1 - np.maximum.accumulate(loss, axis=1))
        self._offsets = generator.uniform(0, SLICE_MM, (self.n_hams, 4))
        for stage in range(4):
            gone = [ham for ham in range(self.n_hams) if ham not in self.hams_at(stage)]
            self.weights[gone, stage] = np.nan
            self.volume_fraction[gone, stage] = np.nan

    def hams_at(self, stage: int) -> list[int]:
        """The hams still in the study at ``stage``: the last ones are withdrawn first.

        Parameters
        ----------
        stage : int
            0 (raw) to 3 (dry-cured).

        Returns
        -------
        list of int
            The hams scanned at that stage.
        """
        stage = check_positive_int(stage, "stage", minimum=0, maximum=3)
        return list(range(self.n_hams - WITHDRAWN_PER_STAGE * stage))

    def _checked(self, ham: object, stage: object) -> tuple[int, int]:
        present, stage = self.hams_at(stage), int(stage)  # hams_at checks stage
        ham = check_positive_int(ham, "ham", minimum=0, maximum=self.n_hams - 1)
        if ham not in present:
            raise ValueError(f"ham {ham} was withdrawn before stage {stage} ({STAGES[stage]})")
        return ham, stage

    def muscle(self, ham: int, stage: int, muscle: str) -> MuscleShape:
        """The solid of ``muscle`` in ``ham`` at ``stage`` (mm).

        Parameters
        ----------
        ham : int
            A ham still in the study at ``stage``.
        stage : int
            0 (raw) to 3 (dry-cured).
        muscle : str
            One of :data:`MUSCLES`.

        Returns
        -------
        MuscleShape
            The shrunk solid.
        """
        ham, stage = self._checked(ham, stage)
        check_choice(muscle, "muscle", MUSCLES)
        return self._muscle(ham, stage, muscle)

    def _muscle(self, ham: int, stage: int, muscle: str) -> MuscleShape:
        factor = self.volume_fraction[ham, stage] ** (1 / 3)
        return self._hams[ham].muscles[muscle]._scaled(factor, self._ham_scale(ham, stage))

    def _ham_scale(self, ham: int, stage: int) -> float:
        return float((self.weights[ham, stage] / self.weights[ham, 0]) ** (1 / 3))

    def slice_positions(self, ham: int, stage: int) -> np.ndarray:
        """Heights (mm) of the slices of ``ham`` at ``stage``, 2 mm apart, through the longer muscle.

        Parameters
        ----------
        ham, stage : int
            As in :meth:`muscle`.

        Returns
        -------
        ndarray
            The heights, ascending.
        """
        ham, stage = self._checked(ham, stage)
        return self._positions(ham, stage)

    def _positions(self, ham: int, stage: int) -> np.ndarray:
        extent = 0.8 * max(self._muscle(ham, stage, name).half_length_mm for name in MUSCLES)
        first = -extent + self._offsets[ham, stage]
        return np.arange(first, extent, SLICE_MM)

    def slice(self, ham: int, stage: int, index: int) -> HamSlice:
        """Render slice ``index`` of ``ham`` at ``stage`` (seeded by the study, the ham, the stage and the index).

        Parameters
        ----------
        ham, stage : int
            As in :meth:`muscle`.
        index : int
            Position in :meth:`slice_positions`.

        Returns
        -------
        HamSlice
            The image and its truth.
        """
        ham, stage = self._checked(ham, stage)
        positions = self._positions(ham, stage)
        index = check_positive_int(index, "index", minimum=0, maximum=len(positions) - 1)
        return self._slice(ham, stage, index)

    def _slice(self, ham: int, stage: int, index: int) -> HamSlice:
        z = float(self._positions(ham, stage)[index])
        muscles = {name: self._muscle(ham, stage, name) for name in MUSCLES}
        anatomy = _Ham(muscles, self._hams[ham].fat_flecks, self._scaled_distractors(ham, stage))
        generator = np.random.default_rng([self._seed, ham, stage, index])
        return _render(anatomy, z, self._ham_scale(ham, stage), generator, self.noise)

    def _scaled_distractors(self, ham: int, stage: int) -> np.ndarray:
        arcs = self._hams[ham].distractors.copy()
        factor = self.volume_fraction[ham, stage] ** (1 / 3)
        centre_factor = self._ham_scale(ham, stage)
        arcs[:, :2] = np.asarray(_HAM_CENTRE) + centre_factor * (arcs[:, :2] - np.asarray(_HAM_CENTRE))
        arcs[:4, 2] *= factor
        return arcs

    def volume(self, ham: int, stage: int, muscle: str) -> float:
        """Exact volume (mm^3) of ``muscle`` in ``ham`` at ``stage``.

        Parameters
        ----------
        ham, stage : int
            As in :meth:`muscle`.
        muscle : str
            One of :data:`MUSCLES`.

        Returns
        -------
        float
            The volume of the solid, mm^3.
        """
        return self.muscle(ham, stage, muscle).volume_mm3()


def make_ham_study(*, rng: int | np.random.Generator, n_hams: int = 15, noise: float = 0.04) -> HamStudy:
    """A seeded ripening study of ``n_hams`` hams at four stages (Sec. 3.2: 15, 12, 9 and 6 hams).

    Parameters
    ----------
    rng : int or numpy.random.Generator
        Seed of the study.
    n_hams : int
        Hams scanned raw, 12 to 1000 (three are withdrawn after each stage).
    noise : float
        Rician noise of every slice, in [0, 0.3].

    Returns
    -------
    HamStudy
        The study; slices are rendered on demand.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 2 and 3.2.

    Examples
    --------
    >>> study = make_ham_study(rng=0)
    >>> [len(study.hams_at(stage)) for stage in range(4)]
    [15, 12, 9, 6]
    """
    return HamStudy(rng, n_hams, noise)


def initial_contour(
    ham_slice: HamSlice,
    muscle: str,
    *,
    rng: int | np.random.Generator,
    enlarge: tuple[float, float] = (0.10, 0.20),
    n_points: int = 60,
) -> np.ndarray:
    """A starting snake round ``muscle``: an ellipse of the muscle's moments, enlarged 10-20 %.

    The paper places its initial snakes "surrounding" the lowest potential values without saying
    how; we draw an ellipse with the true contour's centre and second moments, its axes scaled by
    a factor drawn uniformly in ``1 + enlarge``, and its centre moved by up to one pixel.

    Parameters
    ----------
    ham_slice : HamSlice
        The slice (its true contour gives the ellipse).
    muscle : str
        One of :data:`MUSCLES`, present in the slice.
    rng : int or numpy.random.Generator
        Seed of the enlargement and the offset.
    enlarge : (float, float)
        Range of the linear enlargement, each in [0, 1], low <= high.
    n_points : int
        Points of the snake, 5 to 10,000.

    Returns
    -------
    (n_points, 2) ndarray
        (row, col) pixel coordinates, rounded to whole pixels.

    References
    ----------
    Caro et al., AMDO 2004, Sec. 3.2 ("initial snakes").
    """
    if not isinstance(ham_slice, HamSlice):
        raise TypeError(f"ham_slice must be a HamSlice, got {type(ham_slice).__name__}")
    check_choice(muscle, "muscle", sorted(ham_slice.contours))
    generator = make_rng(rng, "rng")
    low, high = as_finite_array(enlarge, "enlarge", shape=(2,), bounds=(0.0, 1.0))
    if low > high:
        raise ValueError(f"enlarge must be (low, high) with low <= high, got {enlarge}")
    n_points = check_positive_int(n_points, "n_points", minimum=5, maximum=10_000)
    return _initial_contour(ham_slice.contours[muscle], generator, low, high, n_points)


def _initial_contour(truth: np.ndarray, rng: np.random.Generator, low: float, high: float,
                     n_points: int) -> np.ndarray:
    mm = truth * np.asarray(PIXEL_MM)
    centre = mm.mean(axis=0)
    values, vectors = np.linalg.eigh(np.cov((mm - centre).T))
    axes = np.sqrt(2 * values) * (1 + rng.uniform(low, high))
    theta = np.linspace(0, 2 * np.pi, n_points, endpoint=False)
    ellipse = centre + (np.column_stack([np.cos(theta), np.sin(theta)]) * axes) @ vectors.T
    ellipse = ellipse / np.asarray(PIXEL_MM) + rng.uniform(-1, 1, 2)
    limit = np.asarray(IMAGE_SHAPE) - 1
    return np.clip(np.rint(ellipse), 0, limit)
