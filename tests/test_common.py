"""Tests of the shared floor: random generators, validation, geometry, plotting, 3-D helper."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from rejections import check_rejection, reject
from scipy.spatial.transform import Rotation
from sklearn.exceptions import NotFittedError

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from amdo_lab.common import (  # noqa: E402
    apply_rigid,
    apply_similarity_2d,
    as_finite_array,
    as_bool_mask,
    as_image_pair,
    check_axes,
    check_bool,
    check_choice,
    check_fitted,
    check_image_shape,
    check_in_range,
    check_names,
    check_positive,
    check_positive_int,
    make_rng,
    paired_comparison,
    procrustes_align,
    rate_interval,
    rigid_transform,
    rotation_2d,
    rotation_matrix,
    rotation_x,
    rotation_z,
    savefig,
    spawn_rngs,
    use_style,
)
from amdo_lab.common import render3d  # noqa: E402
from amdo_lab.common.geometry import skew  # noqa: E402


# --- random generators -------------------------------------------------------------------------
def test_make_rng_is_reproducible_and_passes_generators_through():
    assert np.array_equal(make_rng(5).normal(size=4), make_rng(5).normal(size=4))
    generator = np.random.default_rng(1)
    assert make_rng(generator) is generator


def test_spawn_rngs_gives_independent_repeatable_streams():
    first, second = spawn_rngs(3, 2)
    again = spawn_rngs(3, 5)
    assert np.array_equal(first.random(3), again[0].random(3))
    assert not np.array_equal(spawn_rngs(3, 2)[0].random(3), second.random(3))


# --- validation --------------------------------------------------------------------------------
def test_as_finite_array_returns_floats_and_casts_whole_numbers_to_int():
    out = as_finite_array([[1, 2, 3]], "points", shape=(None, 3))
    assert out.dtype == float and out.shape == (1, 3)
    assert as_finite_array([2.0, 3.0], "labels", dtype=int).tolist() == [2, 3]
    assert as_finite_array([2.0, -3.0], "counts", dtype=int).tolist() == [2, -3]


def test_scalar_checks():
    assert check_positive(2, "sigma") == 2.0
    assert check_positive(0, "sigma", allow_zero=True) == 0.0


# --- geometry ----------------------------------------------------------------------------------
def test_rotation_matrix_matches_scipy_and_is_a_rotation():
    rng = make_rng(0)
    for _ in range(10):
        axis = rng.normal(size=3)
        angle = rng.uniform(-np.pi, np.pi)
        ours = rotation_matrix(axis, angle)
        reference = Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()
        np.testing.assert_allclose(ours, reference, atol=1e-12)
        np.testing.assert_allclose(ours @ ours.T, np.eye(3), atol=1e-12)
        assert np.isclose(np.linalg.det(ours), 1.0)


def test_rotation_matrix_is_vectorised_over_angles():
    angles = np.linspace(0, 1, 5)
    stacked = rotation_z(angles)
    assert stacked.shape == (5, 3, 3)
    np.testing.assert_allclose(stacked[3], rotation_z(angles[3]))
    np.testing.assert_allclose(rotation_2d(angles)[3], rotation_z(angles[3])[:2, :2], atol=1e-15)


def test_geometry_keeps_accepting_single_points_empty_sets_and_angle_arrays():
    assert apply_rigid(np.eye(4), np.ones(3)).shape == (3,)
    assert apply_rigid(np.eye(4), np.zeros((0, 3))).shape == (0, 3)
    assert rotation_2d(np.zeros((0,))).shape == (0, 2, 2)
    batched = rigid_transform(np.stack([np.eye(3)] * 2), [1.0, 2.0, 3.0])  # one translation for the whole stack
    np.testing.assert_allclose(batched[:, :3, 3], [[1.0, 2.0, 3.0]] * 2)


def test_skew_gives_the_cross_product():
    a, b = make_rng(1).normal(size=(2, 3))
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b))


def test_rigid_transform_round_trip():
    rotation = rotation_x(0.4) @ rotation_z(-1.1)
    transform = rigid_transform(rotation, [1.0, -2.0, 0.5])
    points = make_rng(2).normal(size=(7, 3))
    moved = apply_rigid(transform, points)
    np.testing.assert_allclose(moved, points @ rotation.T + [1.0, -2.0, 0.5])
    np.testing.assert_allclose(apply_rigid(np.linalg.inv(transform), moved), points, atol=1e-12)


@pytest.mark.parametrize("dimension", [2, 3])
def test_procrustes_recovers_a_similarity(dimension):
    rng = make_rng(dimension)
    source = rng.normal(size=(30, dimension))
    rotation = rotation_2d(0.7) if dimension == 2 else rotation_matrix([1, 2, 3], 0.9)
    target = 2.5 * source @ rotation.T + np.arange(dimension)
    fit = procrustes_align(source, target)
    np.testing.assert_allclose(fit.rotation, rotation, atol=1e-10)
    assert fit.scale == pytest.approx(2.5)
    np.testing.assert_allclose(fit.translation, np.arange(dimension), atol=1e-10)
    assert fit.rms_error < 1e-10


def test_procrustes_never_reflects_unless_asked():
    source = make_rng(4).normal(size=(20, 2))
    mirrored = source * [-1.0, 1.0]
    assert np.linalg.det(procrustes_align(source, mirrored).rotation) == pytest.approx(1.0)
    assert np.linalg.det(procrustes_align(source, mirrored, allow_reflection=True).rotation) == pytest.approx(-1.0)


def test_apply_similarity_2d():
    points = np.array([[1.0, 0.0]])
    np.testing.assert_allclose(apply_similarity_2d(points, 2.0, np.pi / 2, [1.0, 1.0]), [[1.0, 3.0]], atol=1e-12)


# --- plotting ----------------------------------------------------------------------------------
def test_savefig_writes_only_when_the_variable_is_set(tmp_path, monkeypatch):
    use_style()
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    monkeypatch.delenv("AMDO_FIG_DIR", raising=False)
    assert savefig(fig, "nothing") is None and not (tmp_path / "figs").exists()
    monkeypatch.setenv("AMDO_FIG_DIR", str(tmp_path / "figs"))
    assert savefig(fig, "fig1_line") is None  # no value, so a figure cell prints no path
    path = tmp_path / "figs" / "fig1_line.png"
    assert path.stat().st_size > 0
    plt.close(fig)


# --- 3-D helper --------------------------------------------------------------------------------
def _sphere_field():
    grid = np.linspace(-1, 1, 21)
    x, y, z = np.meshgrid(grid, grid, grid, indexing="ij")
    return x**2 + y**2 + z**2, grid


def test_isosurface_lies_on_the_level_set():
    field, grid = _sphere_field()
    mesh = render3d.isosurface(field, 0.5, origin=(-1, -1, -1), spacing=(0.1, 0.1, 0.1))
    radii = np.linalg.norm(mesh.vertices, axis=1)
    assert np.allclose(radii, np.sqrt(0.5), atol=0.02)


def test_render_scene_falls_back_to_matplotlib_with_one_warning(monkeypatch):
    field, _ = _sphere_field()
    mesh = render3d.isosurface(field, 0.5)
    monkeypatch.setattr(render3d, "probe_3d_rendering", lambda: render3d._ProbeResult(False, "test"))
    render3d._warn_fallback_once.cache_clear()
    with pytest.warns(RuntimeWarning, match="unavailable"):
        fig = render3d.render_scene([mesh, render3d.PointCloud(np.zeros((3, 3)))])
    assert fig.axes[0].name == "3d"
    plt.close(fig)


def test_render_scene_draws_an_image_when_3d_works():
    if not render3d.probe_3d_rendering().ok:
        pytest.skip("off-screen VTK is unavailable here (the fallback is tested above)")
    field, _ = _sphere_field()
    fig = render3d.render_scene([render3d.isosurface(field, 0.5)], window_size=(120, 90))
    image = fig.axes[0].images[0].get_array()
    assert image.shape[:2] == (90, 120) and np.ptp(image) > 0
    plt.close(fig)


def test_probe_can_be_disabled(monkeypatch):
    monkeypatch.setenv(render3d.DISABLE_3D_VARIABLE, "1")
    render3d.probe_3d_rendering.cache_clear()
    try:
        assert not render3d.probe_3d_rendering().ok
    finally:
        render3d.probe_3d_rendering.cache_clear()


def test_one_blas_thread_limits_blas_and_restores_it():
    from threadpoolctl import threadpool_info, threadpool_limits

    from amdo_lab.common import one_blas_thread

    def blas_threads() -> list[int]:
        return [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]

    assert blas_threads(), "numpy's BLAS should be visible to threadpoolctl"
    with threadpool_limits(2, user_api="blas"):  # a known starting point, even where the environment says 1
        before = blas_threads()
        assert before == [2] * len(before)
        with one_blas_thread():
            assert blas_threads() == [1] * len(before)
            with one_blas_thread():  # nested use, as register_em inside a limited caller
                assert blas_threads() == [1] * len(before)
            assert blas_threads() == [1] * len(before)
        assert blas_threads() == before


def _wilson_by_hand(successes: int, trials: int, z: float) -> tuple[float, float]:
    """Wilson (1927) score interval written out, independent of statsmodels."""
    rate = successes / trials
    centre = (rate + z ** 2 / (2 * trials)) / (1 + z ** 2 / trials)
    half = z * np.sqrt(rate * (1 - rate) / trials + z ** 2 / (4 * trials ** 2)) / (1 + z ** 2 / trials)
    return centre - half, centre + half


@pytest.mark.parametrize("successes, trials", [(93, 100), (0, 20), (20, 20), (1108, 1200), (1, 3)])
def test_rate_interval_is_wilsons(successes, trials):
    from scipy.stats import norm

    outcomes = np.arange(trials) < successes
    interval = rate_interval(outcomes, confidence=0.9)
    low, high = _wilson_by_hand(successes, trials, norm.ppf(0.95))
    assert (interval.successes, interval.trials) == (successes, trials)
    assert interval.low == pytest.approx(low, abs=1e-12) and interval.high == pytest.approx(high, abs=1e-12)
    assert 0 <= interval.low <= interval.rate <= interval.high <= 1
    assert interval.contains(interval.rate) and not interval.contains(interval.high + 1e-9)


def test_rate_interval_narrows_with_more_items():
    widths = [rate_interval(np.arange(n) < 0.9 * n).high - rate_interval(np.arange(n) < 0.9 * n).low
              for n in (20, 100, 1000)]
    assert widths[0] > widths[1] > widths[2]


def test_paired_comparison_counts_and_matches_the_exact_binomial_test():
    from scipy.stats import binomtest

    first = np.array([True] * 50 + [True] * 12 + [False] * 3 + [False] * 35)
    second = np.array([True] * 50 + [False] * 12 + [True] * 3 + [False] * 35)
    result = paired_comparison(first, second)
    assert (result.only_first, result.only_second, result.both, result.neither) == (12, 3, 50, 35)
    assert result.p_value == pytest.approx(binomtest(3, 15, 0.5).pvalue, rel=1e-12)
    assert result.difference == pytest.approx(first.mean() - second.mean())
    assert paired_comparison(second, first).p_value == pytest.approx(result.p_value)
    assert paired_comparison(first, first).p_value == 1.0  # no discordant item


# --- compound checks --------------------------------------------------------------------------
def _axes():
    fig, ax = plt.subplots()
    plt.close(fig)
    return ax


def test_compound_checks_accept_and_copy():
    assert check_bool(np.bool_(True), "flag") is True
    assert check_in_range(1.0, "p", 0, 1, closed="right") == 1.0
    mask = np.array([True, False])
    copied = as_bool_mask(mask, "mask")
    copied[0] = False
    assert mask[0]  # the caller's array is not modified
    a, b = as_image_pair([[1, 2]], [[3, 4]])
    assert a.dtype == float and b.shape == (1, 2)
    ax = _axes()
    assert check_axes(ax) is ax


def test_check_fitted_accepts_a_fitted_model_and_its_error_is_a_value_error():
    from sklearn.exceptions import NotFittedError

    fitted = _Model()
    fitted.coef_ = np.zeros(2)
    assert check_fitted(fitted, ["coef_"]) is None
    assert issubclass(NotFittedError, ValueError)  # callers catching ValueError still catch it


def test_check_names_returns_distinct_names():
    assert check_names(["t", "p"], "random") == ("t", "p")
    assert check_names("p", "random", accept_single=True) == ("p",)
    assert check_names(("fist",), "classes", allowed=("fist", "open")) == ("fist",)



# --- rejections: one table ---------------------------------------------------------------------
# tests/test_bad_input.py already spoils every argument of every public callable (NaN, inf or 1e308
# inside, empty, a wrong trailing axis, one axis more, a string, None, a bool, zero/negative/float counts,
# probabilities outside [0, 1], bad seeds) and checks that the error names the argument. This table holds
# what that test cannot see: the exact wording of the shared validators (every chapter's errors print it),
# the rules of the geometry and of the rates (a non-zero axis, real angles, distinct points, open intervals),
# pairs that must agree, one axis too few, and the 3-D helper's checks.
class _Model:
    """An estimator whose learned attribute is still unset."""

    coef_ = None


REJECTIONS = [
    # --- the shared validators: their wording
    reject("as_finite_array NaN", lambda: as_finite_array([[0, 0, np.nan]], "points", shape=(None, 3)),
           ValueError, r"points must be finite, got 1 NaN"),
    reject("as_finite_array wrong shape", lambda: as_finite_array(np.zeros((4, 2)), "points", shape=(None, 3)),
           ValueError, r"points must have shape \(n, 3\)"),
    reject("as_finite_array empty", lambda: as_finite_array(np.zeros((0, 3)), "points", shape=(None, 3)),
           ValueError, "points must not be empty"),
    reject("as_finite_array strings", lambda: as_finite_array(["a", "b"], "labels"), TypeError, "labels must be a numeric array"),
    reject("as_finite_array booleans", lambda: as_finite_array([True, False], "mask"),
           TypeError, "mask must be a numeric array, got dtype bool"),
    reject("as_finite_array fraction for int", lambda: as_finite_array([1.5, 2.0], "mask", dtype=int),
           ValueError, "mask must hold whole numbers"),
    reject("as_finite_array NaN for int", lambda: as_finite_array([np.nan, 2.0], "mask", dtype=int),
           ValueError, "mask must be finite"),
    # the cast alone would give an arbitrary integer
    reject("as_finite_array 1e308 for int", lambda: as_finite_array([1e308], "counts", dtype=int),
           ValueError, "counts must be at most"),
    reject("as_finite_array beyond max_abs for int", lambda: as_finite_array([5.0], "counts", dtype=int, max_abs=3),
           ValueError, "counts must be at most 3"),
    reject("as_finite_array beyond max_abs", lambda: as_finite_array([1.0, 1e200], "points", max_abs=1e150),
           ValueError, r"points must be at most 1e\+150 in magnitude .* got 1e\+200"),
    reject("check_positive zero", lambda: check_positive(0.0, "sigma"), ValueError, "sigma must be positive"),
    reject("check_positive NaN", lambda: check_positive(float("nan"), "sigma"), ValueError, "sigma must be finite"),
    reject("check_positive_int float", lambda: check_positive_int(2.0, "n_iter"), TypeError, "n_iter must be an int"),
    reject("check_positive_int zero", lambda: check_positive_int(0, "n_iter"), ValueError, "n_iter must be at least 1"),
    reject("check_choice unknown", lambda: check_choice("l3", "metric", ["l2", "soft_l2"]),
           ValueError, "metric must be one of"),
    reject("check_bool string", lambda: check_bool("yes", "verbose"), TypeError, "verbose must be True or False, got str"),
    reject("check_bool int", lambda: check_bool(1, "verbose"), TypeError, "verbose must be True or False, got int"),
    reject("check_in_range open low end", lambda: check_in_range(0.0, "p", 0, 1), ValueError, r"p must be in \(0, 1\), got 0.0"),
    reject("check_in_range open high end", lambda: check_in_range(1.0, "p", 0, 1, closed="left"),
           ValueError, r"p must be in \[0, 1\)"),
    reject("check_in_range NaN", lambda: check_in_range(float("nan"), "p", 0, 1), ValueError, r"p must be finite, got nan"),
    reject("check_in_range bool", lambda: check_in_range(True, "p", 0, 1), TypeError, "p must be a real number, got bool"),
    reject("check_in_range string", lambda: check_in_range("0.5", "p", 0, 1), TypeError, "p must be a real number, got str"),
    reject("as_bool_mask numbers", lambda: as_bool_mask(np.ones(3), "mask"),
           TypeError, "mask must be a boolean array, got dtype float64"),
    reject("as_bool_mask wrong shape", lambda: as_bool_mask(np.ones((2, 2), bool), "mask", shape=(3, 3)),
           ValueError, r"mask must have shape \(3, 3\)"),
    reject("as_image_pair shapes differ", lambda: as_image_pair(np.ones((2, 2)), np.ones((2, 3))), ValueError,
           r"template and study must have the same shape, got \(2, 2\) and \(2, 3\)"),
    reject("check_axes string", lambda: check_axes("not axes"), TypeError, "ax must be a matplotlib Axes, got str"),
    reject("check_fitted unset attribute", lambda: check_fitted(_Model(), "coef_"), NotFittedError,
           r"_Model is not fitted yet.*missing: coef_"),
    reject("check_names a string", lambda: check_names("fist", "classes"),  # its letters are not names
           TypeError, "classes must be a sequence of names"),
    reject("check_names empty", lambda: check_names([], "classes"), ValueError, "classes must hold at least one name"),
    reject("check_names blank name", lambda: check_names(["t", " "], "random"), TypeError, "random must hold non-empty strings"),
    reject("check_names unknown", lambda: check_names(["fist", "wave"], "classes", allowed=("fist", "open")),
           ValueError, r"classes holds unknown name\(s\) \['wave'\]"),
    reject("check_names repeated", lambda: check_names(["t", "t"], "random"), ValueError, "random must not repeat a name"),
    reject("make_rng negative", lambda: make_rng(-1, "rng"), ValueError, "rng must be non-negative, got -1"),
    reject("make_rng float", lambda: make_rng(1.5, "rng"), TypeError,
           "rng must be a non-negative int or a numpy.random.Generator"),
    # --- geometry
    reject("rotation_matrix zero axis", lambda: rotation_matrix(np.zeros(3), 0.3), ValueError, "non-zero"),
    reject("rotation_z complex angle", lambda: rotation_z(1j), TypeError, "angle must be real-valued"),
    reject("rigid_transform 1-D rotation", lambda: rigid_transform(np.ones(3), np.zeros(3)),
           ValueError, "rotation must be a square"),
    reject("rigid_transform two rotations, three translations",
           lambda: rigid_transform(np.stack([np.eye(3)] * 2), np.zeros((3, 3))), ValueError, "translation must have shape"),
    reject("apply_similarity_2d two angles", lambda: apply_similarity_2d(np.ones((2, 2)), 1.0, [0.0, 1.0], [0, 0]),
           ValueError, "angle must have 0 dimensions"),
    reject("procrustes_align boolean source", lambda: procrustes_align(np.eye(3, dtype=bool), np.eye(3)),
           TypeError, "source must be a numeric array"),
    # 78 identical points: their mean has round-off, so their variance is ~1e-32 rather than 0
    reject("procrustes_align identical points", lambda: procrustes_align(np.ones((78, 2)), make_rng(0).normal(size=(78, 2))),
           ValueError, "source points are all identical"),
    reject("procrustes_align sets differ", lambda: procrustes_align(np.ones((20, 2)), np.ones((5, 2))),
           ValueError, "same shape"),
    # --- rates
    reject("rate_interval confidence 1", lambda: rate_interval(np.ones(3, dtype=bool), confidence=1.0),
           ValueError, "confidence"),
    reject("paired_comparison items differ", lambda: paired_comparison(np.ones(3, dtype=bool), np.ones(4, dtype=bool)),
           ValueError, "first and second must have the same shape"),
    # --- plotting and the 3-D helper
    reject("savefig name escapes the folder", lambda: savefig(_axes().figure, "../escape"), ValueError, "name must be"),
    reject("isosurface level outside the field", lambda: render3d.isosurface(_sphere_field()[0], 5.0),
           ValueError, r"level must be in \("),
    reject("render_scene a name for an item", lambda: render3d.render_scene(["sphere"]), TypeError, r"items\[0\]"),
    reject("render_scene nothing", lambda: render3d.render_scene([]), ValueError, "at least one"),
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


def test_check_image_shape_returns_python_ints_and_names_the_argument():
    assert check_image_shape(np.array([6, 5]), "size", minimum=2) == (6, 5)
    with pytest.raises(ValueError, match=r"size must be a pair \(H, W\)"):
        check_image_shape((6, 5, 3), "size", axes="H, W")
    with pytest.raises(ValueError, match=r"size\[1\] must be at least 2"):
        check_image_shape((6, 1), "size", minimum=2)
    with pytest.raises(TypeError, match=r"size\[0\] must be an int"):
        check_image_shape((6.5, 5), "size")


# --- bad input, round 2: bounded counts, scale-safe norms, flags and records of the shared floor -----

def test_count_checks_take_a_maximum():
    from amdo_lab.common import check_positive_int

    assert check_positive_int(1000, "n_iter", maximum=1000) == 1000
    with pytest.raises(ValueError, match=r"n_iter must be at most 1,000, got 1,000,000,000"):
        check_positive_int(10**9, "n_iter", maximum=1000)


@pytest.mark.parametrize("n", [10**9, 2**63])
def test_spawn_rngs_refuses_a_count_it_cannot_make_in_seconds(n):
    from amdo_lab.common import spawn_rngs

    with pytest.raises(ValueError, match=r"\bn must be at most"):
        spawn_rngs(0, n)


@pytest.mark.parametrize("scale", [1e-200, 1.0, 1e200, 1e300])
def test_rotation_matrix_is_scale_free_in_its_axis(scale):
    from amdo_lab.common import rotation_matrix, rotation_x

    np.testing.assert_allclose(rotation_matrix(np.array([scale, 0.0, 0.0]), 0.9), rotation_x(0.9), atol=1e-15)


@pytest.mark.parametrize("matrix", [2 * np.eye(3), np.diag([1.0, 1.0, -1.0]), np.ones((3, 3))])
def test_rigid_transform_refuses_a_matrix_that_is_not_a_rotation(matrix):
    from amdo_lab.common import rigid_transform

    with pytest.raises(ValueError, match=r"rotation must be a rotation"):
        rigid_transform(matrix, np.zeros(3))


def test_apply_rigid_refuses_points_whose_image_overflows():
    from amdo_lab.common import apply_rigid, rigid_transform, rotation_z

    transform = rigid_transform(rotation_z(0.8), np.array([0.0, 1e308, 0.0]))
    with pytest.raises(ValueError, match=r"points and transform are too large"):
        apply_rigid(transform, np.full((2, 3), 1e308))


@pytest.mark.parametrize("flag", ["allow_scale", "allow_reflection"])
@pytest.mark.parametrize("value", ["no", None, 2])
def test_procrustes_flags_must_be_bools(flag, value):
    from amdo_lab.common import procrustes_align

    points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    with pytest.raises(TypeError, match=rf"\b{flag} must be True or False"):
        procrustes_align(points, 2 * points, **{flag: value})


@pytest.mark.parametrize("value", [None, True, "0.5", float("nan")])
def test_rate_interval_contains_refuses_what_is_not_a_number(value):
    from amdo_lab.common import rate_interval

    interval = rate_interval(np.array([True] * 5 + [False] * 5))
    with pytest.raises((TypeError, ValueError), match=r"\bvalue must be"):
        interval.contains(value)


def test_as_finite_array_bounds_name_the_first_element_outside():
    assert as_finite_array([0.0, 1.0], "weights", bounds=(0, 1)).tolist() == [0.0, 1.0]
    with pytest.raises(ValueError, match=r"weights must lie in \(0, 1\], got 0 at index 0"):
        as_finite_array([0.0, 1.0], "weights", bounds=(0, 1), closed="right")
    with pytest.raises(ValueError, match=r"pixel_mm must lie in \(0, inf\), got -0.2 at index \(1, 0\)"):
        as_finite_array([[0.2, 0.2], [-0.2, 0.1]], "pixel_mm", bounds=(0, np.inf), closed="neither")


def test_check_odd_int_and_check_dataframe():
    from amdo_lab.common import check_dataframe, check_odd_int

    assert check_odd_int(5, "window") == 5
    with pytest.raises(ValueError, match="window must be odd"):
        check_odd_int(4, "window")
    with pytest.raises(ValueError, match="window must be at least 3"):
        check_odd_int(1, "window")
    frame = pd.DataFrame({"correct": [1, 0]})
    assert check_dataframe(frame, "table", columns=["correct"]) is frame
    with pytest.raises(TypeError, match="table must be a pandas DataFrame, got dict"):
        check_dataframe({"correct": [1]}, "table")
    with pytest.raises(ValueError, match=r"table must have columns \['correct', 'subject'\], missing \['subject'\]"):
        check_dataframe(frame, "table", columns=("correct", "subject"))


def test_particle_weights_resampling_and_planar_chain():
    from amdo_lab.common import effective_sample_size, normalised_weights, planar_chain, systematic_resample

    weights = normalised_weights(np.array([-2000.0, -2001.0, -2003.0]))  # exp alone underflows to 0
    assert np.isclose(weights.sum(), 1.0) and weights[0] > weights[1] > weights[2] > 0
    assert effective_sample_size(np.full(5, 0.2)) == pytest.approx(5.0)
    assert effective_sample_size(np.array([1.0, 0.0])) == pytest.approx(1.0)
    counts = np.bincount(systematic_resample(np.array([0.5, 0.3, 0.2]), 0.1), minlength=3)
    assert counts.tolist() == [2, 1, 0]  # floor or ceil of N w_i copies
    joints = planar_chain(np.array([np.pi / 2, -np.pi / 2]), np.array([2.0, 3.0]), base=(1.0, 1.0))
    assert np.allclose(joints, [[1.0, 1.0], [1.0, 3.0], [4.0, 3.0]])
