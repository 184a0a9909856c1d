"""Tests of amdo_lab.cat_fluid (Bentabet & Ziou, AMDO 2004): complex, stencil, solvers, registration."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from rejections import check_rejection, reject

from amdo_lab import cat_fluid as cf
from amdo_lab.cat_fluid.data import _smooth_warp
from amdo_lab.cat_fluid.registration import (MAX_GREY_LEVEL, _compose, check_registration_images,
                                             sample_bilinear)
from amdo_lab.cat_fluid.solvers import _apply_finite_difference, _stencil_matrix
from amdo_lab.common import make_rng

LAM, MU = 1.0, 5.0


# --- the CAT image model (Sec. 2) -------------------------------------------------------------

@pytest.mark.parametrize("shape", [(2, 2), (3, 5), (6, 4)])
def test_boundary_of_boundary_and_coboundary_of_coboundary_vanish(shape):
    complex_ = cf.CubicalComplex(shape)
    assert (complex_.boundary(1) @ complex_.boundary(2)).count_nonzero() == 0
    assert (complex_.coboundary(1) @ complex_.coboundary(0)).count_nonzero() == 0
    n0, n1, n2 = complex_.n_pixels
    assert complex_.boundary(1).shape == (n0, n1) and complex_.boundary(2).shape == (n1, n2)
    assert n0 - n1 + n2 == 1  # Euler characteristic of a filled rectangle


def test_each_square_has_four_edges_and_each_edge_two_ends():
    complex_ = cf.CubicalComplex((4, 5))
    assert np.all(np.abs(complex_.boundary(2)).sum(axis=0) == 4)
    assert np.all(complex_.boundary(1).sum(axis=0) == 0)  # head - tail
    assert np.all(np.abs(complex_.boundary(1)).sum(axis=0) == 2)


def test_coboundary_of_a_zero_cochain_is_the_difference_of_end_values():
    """Eq. (7): D_1(γ) = Ψ_0(x_*) - Ψ_0(x_#) on every 1-face."""
    complex_ = cf.CubicalComplex((5, 7))
    values = make_rng(0).normal(size=complex_.n_pixels[0])
    tails, heads = complex_.edges()
    np.testing.assert_allclose(complex_.coboundary(0) @ values, values[heads] - values[tails])
    # on the image layout: horizontal edges carry the difference along axis 1
    grid = values.reshape(5, 7)
    np.testing.assert_allclose((complex_.coboundary(0) @ values)[:5 * 6], np.diff(grid, axis=1).ravel())


def test_coboundary_of_a_one_cochain_is_its_circulation():
    complex_ = cf.CubicalComplex((3, 3))
    tails, heads = complex_.edges()
    coords = np.stack(np.unravel_index(np.arange(9), (3, 3)), axis=1).astype(float)
    # the 1-cochain of the rotation field (-x2, x1) integrated along each edge
    mid = 0.5 * (coords[tails] + coords[heads])
    step = coords[heads] - coords[tails]
    circulation = mid[:, 0] * step[:, 1] - mid[:, 1] * step[:, 0]
    # the square's orientation is counter-clockwise in the (axis 1, axis 0) plane: curl -2 per unit area
    np.testing.assert_allclose(complex_.coboundary(1) @ circulation, -2.0)


# --- the stencil (Sec. 4, eqs. 8-15) ---------------------------------------------------------

def continuous_operator(kind: str, lam: float, mu: float) -> np.ndarray:
    """μΔv + (λ+μ)∇(∇·v) of the quadratic fields below, worked out by hand."""
    return {"x1^2": np.array([2 * lam + 4 * mu, 0.0]),  # μ·2 + (λ+μ)·2 on component 1
            "x2^2": np.array([2 * mu, 0.0]),
            "x1x2": np.array([0.0, lam + mu]),        # ∇·v = x2, so (λ+μ)∇x2
            "v2=x2^2": np.array([0.0, 2 * lam + 4 * mu]),
            "v2=x1^2": np.array([0.0, 2 * mu]),
            "v2=x1x2": np.array([lam + mu, 0.0])}[kind]


QUADRATIC_FIELDS = {
    "x1^2": lambda x1, x2: (x1 ** 2, 0.0), "x2^2": lambda x1, x2: (x2 ** 2, 0.0),
    "x1x2": lambda x1, x2: (x1 * x2, 0.0), "v2=x2^2": lambda x1, x2: (0.0, x2 ** 2),
    "v2=x1^2": lambda x1, x2: (0.0, x1 ** 2), "v2=x1x2": lambda x1, x2: (0.0, x1 * x2),
}
LOW_ORDER_FIELDS = [lambda x1, x2: (1.0, 0.0), lambda x1, x2: (0.0, 1.0), lambda x1, x2: (x1, 0.0),
                    lambda x1, x2: (x2, 0.0), lambda x1, x2: (0.0, x1), lambda x1, x2: (0.0, x2),
                    lambda x1, x2: (3 - 2 * x1 + x2, 1 + x1 - 4 * x2)]


@pytest.mark.parametrize("lam, mu", [(1.0, 5.0), (0.0, 1.0), (2.5, 0.5)])
def test_derived_stencil_gives_zero_force_on_constant_and_linear_fields(lam, mu):
    stencil = cf.fluid_stencil(lam, mu)
    for field in LOW_ORDER_FIELDS:
        np.testing.assert_allclose(cf.stencil_at_origin(stencil, field), 0.0, atol=1e-12)


@pytest.mark.parametrize("lam, mu", [(1.0, 5.0), (0.0, 1.0), (2.5, 0.5)])
@pytest.mark.parametrize("kind", list(QUADRATIC_FIELDS))
def test_derived_stencil_reproduces_the_continuous_operator_on_quadratics(kind, lam, mu):
    """Sign convention: stencil · v ≈ +[μΔv + (λ+μ)∇(∇·v)] (internal force, negative centre)."""
    got = cf.stencil_at_origin(cf.fluid_stencil(lam, mu), QUADRATIC_FIELDS[kind])
    np.testing.assert_allclose(got, continuous_operator(kind, lam, mu), atol=1e-12)


def test_derived_stencil_is_invariant_under_a_quarter_turn():
    """The v_2 row is the 90° rotation of the v_1 row."""
    stencil = cf.fluid_stencil(LAM, MU)
    np.testing.assert_allclose(cf.rotate_stencil(stencil), stencil, atol=1e-12)


def test_derived_stencil_exact_values():
    """The integrals in closed form (our derivation, in the order of NEIGHBOUR_OFFSETS)."""
    lam, mu = 2.0, 3.0
    blocks = cf.stencil_blocks(cf.fluid_stencil(lam, mu))
    index = {offset: p for p, offset in enumerate(cf.NEIGHBOUR_OFFSETS)}
    np.testing.assert_allclose(blocks[index[(0, 0)]], np.diag([-4.5 * mu - 1.5 * lam] * 2))
    np.testing.assert_allclose(blocks[index[(1, 0)]], np.diag([1.25 * mu + 0.75 * lam, 0.25 * (mu - lam)]))
    np.testing.assert_allclose(blocks[index[(0, -1)]], np.diag([0.25 * (mu - lam), 1.25 * mu + 0.75 * lam]))
    diagonal = 0.375 * mu + 0.125 * lam
    for offset, sign in [((1, 1), 1), ((-1, -1), 1), ((1, -1), -1), ((-1, 1), -1)]:
        np.testing.assert_allclose(blocks[index[offset]], [[diagonal, sign * 0.25 * (mu + lam)],
                                                           [sign * 0.25 * (mu + lam), diagonal]])


def test_printed_stencil_matches_derivation_up_to_three_sign_slips_and_a_row():
    derived, printed = cf.fluid_stencil(LAM, MU), cf.printed_stencil(LAM, MU)
    # the μ parts of row 1 agree except the signs of two cross-diagonal coefficients
    same_mu = cf.fluid_stencil(0.0, 1.0), cf.printed_stencil(0.0, 1.0)
    differs = ~np.isclose(same_mu[0][0], same_mu[1][0])
    assert [2 * p + 1 for p in range(9) if differs[2 * p + 1]] == [13, 15]  # k_{1,14}, k_{1,16}
    np.testing.assert_allclose(np.abs(same_mu[0][0]), np.abs(same_mu[1][0]))
    # the λ parts of the centre and the own-axis edges have the opposite sign
    lam_derived = cf.fluid_stencil(1.0, 0.0)[0]
    lam_printed = cf.printed_stencil(1.0, 0.0)[0]
    np.testing.assert_allclose(lam_printed[[0, 4, 10]], -lam_derived[[0, 4, 10]])
    assert not np.allclose(derived, printed)


def test_printed_stencil_fails_the_consistency_checks():
    printed = cf.printed_stencil(LAM, MU)
    constant_v2 = cf.stencil_at_origin(printed, lambda x1, x2: (0.0, 1.0))
    assert abs(constant_v2[0]) > 1.0  # a uniform flow would feel a force
    quadratic = cf.stencil_at_origin(printed, QUADRATIC_FIELDS["x1^2"])
    assert not np.allclose(quadratic, continuous_operator("x1^2", LAM, MU))
    assert not np.allclose(cf.rotate_stencil(printed), printed)


def test_stencil_symbol_of_the_printed_stencil():
    """At ω = 0 the symbol is the sum of the nine blocks: the force on a uniform velocity."""
    printed = cf.printed_stencil(LAM, MU)
    symbol = cf.stencil_symbol(printed, (8, 8))
    np.testing.assert_allclose(symbol[:, :, 0, 0], cf.stencil_blocks(printed).sum(axis=0))
    np.testing.assert_allclose(cf.stencil_symbol(cf.fluid_stencil(LAM, MU), (8, 8))[:, :, 0, 0], 0.0, atol=1e-12)


def test_periodic_stencil_conserves_momentum_and_matches_its_symbol():
    """Σ_x force = 0 (the dual cells' fluxes cancel), and apply_stencil inverts the symbol solve."""
    rng = make_rng(1)
    velocity = rng.normal(size=(2, 12, 10))
    force = cf.apply_stencil(cf.fluid_stencil(LAM, MU), velocity)
    np.testing.assert_allclose(force.sum(axis=(1, 2)), 0.0, atol=1e-10)
    solved = cf.solve_velocity(force, "cat", LAM, MU)
    np.testing.assert_allclose(solved, velocity - velocity.mean(axis=(1, 2), keepdims=True), atol=1e-10)


@pytest.mark.parametrize("symbol", [cf.cat_symbol, cf.finite_difference_symbol])
def test_both_discretisations_approach_the_continuous_symbol_at_low_frequency(symbol):
    n = 256
    got = symbol((n, n), LAM, MU)[:, :, 1, 2]  # ω = 2π (1, 2) / n
    omega = 2 * np.pi * np.array([1, 2]) / n
    expected = -(MU * omega @ omega * np.eye(2) + (LAM + MU) * np.outer(omega, omega))
    np.testing.assert_allclose(got, expected, rtol=2e-3)


def test_cat_operator_is_negative_definite_except_the_uniform_mode():
    symbol = cf.cat_symbol((16, 16), LAM, MU)
    eigen = np.linalg.eigvalsh(np.moveaxis(symbol, (0, 1), (-2, -1)))
    assert np.all(eigen.reshape(-1, 2)[1:] < -1e-6) and np.allclose(eigen[0, 0], 0.0)


# --- solvers -----------------------------------------------------------------------------

def test_fft_solve_inverts_the_finite_difference_operator():
    force = make_rng(2).normal(size=(2, 16, 20))
    velocity = cf.solve_velocity(force, "fft", LAM, MU)
    np.testing.assert_allclose(_apply_finite_difference(velocity, LAM, MU),
                               force - force.mean(axis=(1, 2), keepdims=True), atol=1e-10)


@pytest.mark.parametrize("omega", [1.6, 1.9])
def test_sor_converges_to_the_fft_solution(omega):
    force = make_rng(3).normal(size=(2, 24, 32))
    exact = cf.solve_velocity(force, "fft", LAM, MU)
    sor = cf.sor_solve(force, LAM, MU, n_sweeps=800, omega=omega)
    np.testing.assert_allclose(sor, exact, atol=1e-6 * np.abs(exact).max())


def test_red_black_with_both_components_at_once_diverges_at_high_omega():
    """The paper's checkerboard: fine component by component, divergent when both components of a
    colour are relaxed together (the mixed term couples same-colour diagonal neighbours)."""
    force = make_rng(7).normal(size=(2, 16, 16))
    exact = cf.solve_velocity(force, "fft", LAM, MU)

    def error(ordering, omega):
        return np.linalg.norm(cf.sor_solve(force, LAM, MU, n_sweeps=200, omega=omega, ordering=ordering) - exact)

    scale = np.linalg.norm(exact)
    assert error("four-colour", 1.9) < 1e-8 * scale and error("red-black", 1.9) < 1e-8 * scale
    assert error("red-black-together", 1.5) < 1e-3 * scale
    assert error("red-black-together", 1.9) > 1e3 * scale


def test_sor_error_shrinks_with_sweeps_and_warm_start_continues():
    force = make_rng(4).normal(size=(2, 32, 32))
    exact = cf.solve_velocity(force, "fft", LAM, MU)
    errors = [np.linalg.norm(cf.sor_solve(force, LAM, MU, n_sweeps=k) - exact) for k in (5, 20, 80)]
    assert errors[0] > errors[1] > errors[2]
    warm = cf.sor_solve(force, LAM, MU, n_sweeps=60, initial=cf.sor_solve(force, LAM, MU, n_sweeps=20))
    assert np.linalg.norm(warm - exact) < errors[1]


# --- registration pieces -----------------------------------------------------------------

def test_warp_image_against_a_known_shift():
    rows, cols = np.indices((20, 24), dtype=float)
    image = 2.0 * rows - 0.5 * cols + 0.1 * rows * cols
    shift = np.array([2.5, -1.25])
    warped = cf.warp_image(image, np.broadcast_to(shift[:, None, None], (2, 20, 24)))
    expected = 2.0 * (rows - 2.5) - 0.5 * (cols + 1.25) + 0.1 * (rows - 2.5) * (cols + 1.25)
    inside = (slice(3, None), slice(None, -2))  # where x - u stays inside the image
    # bilinear interpolation is exact on each cell for a bilinear image
    np.testing.assert_allclose(warped[inside], expected[inside], atol=1e-9)
    np.testing.assert_allclose(cf.warp_image(image, np.zeros((2, 20, 24))), image)


@pytest.mark.parametrize("shape", [(1, 5), (5, 1), (2, 2), (7, 9), (16, 12)])
def test_bilinear_sampling_matches_scipy_map_coordinates(shape):
    """Our fast sampler against scipy's order-1 interpolation, coordinates inside and outside."""
    from scipy.ndimage import map_coordinates

    rng = make_rng(11)
    image = rng.random(shape)
    coords = rng.uniform(-3.0, max(shape) + 3.0, size=(2,) + shape)
    np.testing.assert_allclose(sample_bilinear(image, coords), map_coordinates(image, coords, order=1, mode="nearest"),
                               atol=1e-12)


def test_material_update_follows_the_flow_with_the_untransposed_jacobian():
    """Eq. (16) read as u + Δt (v - J v), J[i, j] = ∂u_i/∂x_j: transporting the deformed template
    T(x - u) by a uniform velocity v for Δt gives exactly u(x - vΔt) + vΔt. Our reading is off
    at second order in Δt, the other reading ((∇u) untransposed, J swapped) at first order."""
    rows, cols = np.indices((40, 40), dtype=float)

    def displacement(r, c):  # quadratic, with a non-symmetric Jacobian
        return np.stack([0.002 * r * c + 0.004 * c ** 2, 0.003 * r ** 2 - 0.1 * c])

    v = np.array([1.0, 2.0])
    velocity = np.broadcast_to(v[:, None, None], (2, 40, 40))
    u, dt = displacement(rows, cols), 0.1
    exact = displacement(rows - dt * v[0], cols - dt * v[1]) + dt * velocity
    ours = cf.material_update(u, velocity, dt)
    jac = cf.displacement_jacobian(u)
    swapped = u + dt * (velocity - np.einsum("jihw,jhw->ihw", jac, velocity))
    interior = (slice(None), slice(1, -1), slice(1, -1))  # central differences are exact there
    assert np.abs(ours - exact)[interior].max() < 1e-3 < np.abs(swapped - exact)[interior].max()


def test_compose_then_warp_equals_warping_twice():
    rng = make_rng(5)
    image = cf.load_dipy_image("t1_coronal_slice")[64:192, 64:192]
    first = _smooth_warp(image.shape, rng, 3.0)
    second = _smooth_warp(image.shape, rng, 3.0)
    twice = cf.warp_image(cf.warp_image(image, first), second)
    once = cf.warp_image(image, _compose(first, second))
    assert np.abs(twice - once)[8:-8, 8:-8].mean() < 0.01


def test_external_force_points_down_the_ssd_gradient():
    """Eq. (18) with L v = F and L negative: v ∝ -F to first order, which must lower the SSD."""
    pair = cf.make_pair("C", rng=0)
    force = cf.external_force(pair.template, pair.study)
    velocity = cf.solve_velocity(force, "cat", LAM, MU)
    before = np.sum((pair.template - pair.study) ** 2)
    small = 0.2 / np.abs(velocity).max()
    after = np.sum((cf.warp_image(pair.template, small * velocity) - pair.study) ** 2)
    assert after < before


@pytest.mark.parametrize("method", ["cat", "fft"])
@pytest.mark.parametrize("name", ["A", "C"])
def test_registration_reduces_the_residual_without_folds(method, name):
    pair = cf.make_pair(name, rng=0)
    result = cf.register_fluid(pair.template, pair.study, method=method)
    assert result.residuals[-1] < 0.8 * result.residuals[0]
    assert np.all(np.diff(result.history[:, 1]) >= 0)
    assert cf.jacobian_determinant(result.displacement).min() > 0
    np.testing.assert_allclose(result.warped, cf.warp_image(pair.template, result.displacement), atol=1e-12)
    rmse = cf.displacement_rmse(result.displacement, pair.true_displacement, pair.mask)
    assert rmse < cf.displacement_rmse(np.zeros_like(result.displacement), pair.true_displacement, pair.mask)


def test_sor_registration_on_a_small_image():
    pair = cf.make_pair("C", rng=0)
    template, study = pair.template[::4, ::4], pair.study[::4, ::4]  # 64 x 64
    result = cf.register_fluid(template, study, method="sor", n_iter=10, sor_n_sweeps=30)
    assert result.history.shape == (11, len(cf.HISTORY_COLUMNS))
    assert result.residuals[-1] < 0.8 * result.residuals[0]
    assert cf.jacobian_determinant(result.displacement).min() > 0


def test_regridding_keeps_the_map_unfolded():
    pair = cf.make_pair("C", rng=0)
    result = cf.register_fluid(pair.template, pair.study, "cat", n_iter=10, max_step_px=3.0, backtrack=False,
                               regrid_threshold=0.9)
    assert result.n_regrids >= 1
    assert cf.jacobian_determinant(result.displacement).min() > 0


def test_identical_images_stay_put_without_warnings():
    """No force anywhere: a zero velocity, no step, no division by zero."""
    image = cf.make_pair("C", rng=0).template[::4, ::4]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for method in cf.SOLVERS:
            result = cf.register_fluid(image, image, method=method, n_iter=3, sor_n_sweeps=5)
            assert np.all(result.displacement == 0) and np.all(result.residuals == 0)
            np.testing.assert_array_equal(result.warped, image)


def test_inverse_consistency_error_is_zero_for_exact_inverses():
    shift = np.broadcast_to(np.array([1.5, -2.0])[:, None, None], (2, 16, 16))
    assert cf.inverse_consistency_error(shift, -shift) < 1e-12
    assert cf.inverse_consistency_error(shift, shift) == pytest.approx(5.0)


def test_grey_level_difference_in_a_mask():
    image, reference = np.arange(16.0).reshape(4, 4), np.zeros((4, 4))
    mask = image >= 8
    assert cf.grey_level_difference(image, reference, mask) == (pytest.approx(11.5), pytest.approx(np.std(np.arange(8.0, 16))))


def test_displacement_rmse_in_a_mask():
    zero, one = np.zeros((2, 4, 4)), np.ones((2, 4, 4))
    assert cf.displacement_rmse(zero, one, np.eye(4, dtype=bool)) == pytest.approx(np.sqrt(2))


# --- data ---------------------------------------------------------------------------------

def test_pairs_are_deterministic_and_their_warps_unfolded():
    for name in cf.PAIR_NAMES:
        pair = cf.make_pair(name, rng=0)
        again = cf.make_pair(name, rng=0)
        np.testing.assert_array_equal(pair.study, again.study)
        assert pair.template.shape == pair.study.shape == (256, 256)
        assert cf.jacobian_determinant(pair.true_displacement).min() > 0.5
        assert 0.1 < pair.mask.mean() < 0.4


def test_dipy_peer_uses_our_displacement_convention():
    pair = cf.make_pair("C", rng=0)
    template, study = pair.template[::4, ::4], pair.study[::4, ::4]
    result = cf.register_dipy(template, study, level_iters=(10, 5))
    np.testing.assert_allclose(cf.warp_image(template, result.displacement), result.warped, atol=1e-5)


def test_sor_cold_start_differs_from_the_warm_start():
    pair = cf.make_pair("C", rng=0)
    template, study = pair.template[::4, ::4], pair.study[::4, ::4]
    warm = cf.register_fluid(template, study, method="sor", n_iter=4, sor_n_sweeps=3)
    cold = cf.register_fluid(template, study, method="sor", n_iter=4, sor_n_sweeps=3, sor_warm_start=False)
    # the first solve starts from zero either way; later ones differ only in their start
    assert not np.allclose(warm.displacement, cold.displacement)
    assert cold.residuals[-1] < cold.residuals[0]


# --- reference paths beside the fast ones, and the chapter's helpers ---------------------------

def test_stencil_matrix_is_apply_stencil_pixel_by_pixel():
    """Eq. (15) at every pixel: the sparse matrix (reference) equals the rolled sum (fast path)."""
    stencil = cf.fluid_stencil(LAM, MU)
    velocity = make_rng(1).normal(size=(2, 6, 8))
    by_matrix = (_stencil_matrix(cf.stencil_blocks(stencil), (6, 8)) @ velocity.ravel()).reshape(2, 6, 8)
    np.testing.assert_allclose(by_matrix, cf.apply_stencil(stencil, velocity), atol=1e-12)


@pytest.mark.parametrize("shape", [(8, 8), (6, 10)])
def test_dense_reference_solve_equals_the_fourier_solve(shape):
    force = make_rng(2).normal(size=(2,) + shape)
    reference = cf.solve_stencil_reference(cf.fluid_stencil(LAM, MU), force)
    np.testing.assert_allclose(reference, cf.solve_velocity(force, "cat", LAM, MU), atol=1e-10)


@pytest.mark.parametrize("ordering_sweeps, omega", [(1, 1.0), (4, 1.7)])
def test_pixel_loop_sor_equals_the_vectorised_four_colour_sor(ordering_sweeps, omega):
    force = make_rng(3).normal(size=(2, 8, 6))
    loop = cf.sor_reference(force, LAM, MU, n_sweeps=ordering_sweeps, omega=omega)
    np.testing.assert_allclose(loop, cf.sor_solve(force, LAM, MU, n_sweeps=ordering_sweeps, omega=omega), atol=1e-12)


def test_symbol_eigenvalues_along_a_path():
    symbol = cf.cat_symbol((16, 16), LAM, MU)
    k = np.arange(9)
    eigen = cf.symbol_eigenvalues(symbol, np.zeros_like(k), k)
    assert eigen.shape == (9, 2) and np.all(eigen[:, 0] <= eigen[:, 1])
    np.testing.assert_allclose(eigen[0], 0.0, atol=1e-12)  # the uniform velocity costs no stress
    # along x2 the two waves are shear (μ) and compression (λ + 2μ): ratio (λ + 2μ)/μ
    np.testing.assert_allclose(eigen[1:, 0] / eigen[1:, 1], (LAM + 2 * MU) / MU)


def test_stencil_grid_lays_out_one_block():
    stencil = cf.fluid_stencil(LAM, MU)
    grid = cf.stencil_grid(stencil, 0, 0)
    assert grid[1, 1] == stencil[0, 0] and grid[2, 1] == stencil[0, 4]  # neighbour (1, 0) is column 5
    np.testing.assert_allclose(cf.stencil_grid(stencil, 1, 1), cf.stencil_grid(stencil, 0, 0).T)


def test_consistency_errors_of_the_derived_and_printed_stencils():
    derived = cf.consistency_errors(cf.fluid_stencil(LAM, MU), LAM, MU)
    printed = cf.consistency_errors(cf.printed_stencil(LAM, MU), LAM, MU)
    assert len(derived) == len(cf.polynomial_test_fields(LAM, MU)) + 1 == 13
    assert max(derived.values()) < 1e-12
    assert sum(error > 1e-9 for error in printed.values()) == 9


def test_make_pair_accepts_a_generator_and_keeps_its_int_seed_streams():
    by_seed = cf.make_pair("B", rng=4)
    by_generator = cf.make_pair("B", rng=make_rng(4 + cf.PAIR_NAMES.index("B")))
    np.testing.assert_array_equal(by_seed.study, by_generator.study)
    assert not np.array_equal(cf.make_pair("B", rng=5).study, by_seed.study)


def test_table1_helpers():
    paper = cf.paper_table1()
    assert paper.loc["A", ("paper SOR", "mean")] == 10.9 and paper.shape == (3, 4)
    pair = cf.make_pair("C", rng=0)
    table = cf.grey_level_table({"C": pair}, {"C": {"none": pair.template, "truth": cf.warp_image(pair.template, pair.true_displacement)}})
    assert table.loc["C", ("truth", "mean")] < 1e-9 < table.loc["C", ("none", "mean")]
    masked = cf.grey_level_table({"C": pair}, {"C": {"none": pair.template}}, masked=True)
    assert masked.loc["C", ("none", "mean")] > table.loc["C", ("none", "mean")]  # background dilutes the mean
    assert cf.mean_sd_strings(paper).loc["B", "paper CAT"] == "6.80 / 13.80"
    row = cf.accuracy_row(pair, pair.template, np.zeros_like(pair.true_displacement))
    assert row["min det"] == 1.0 and row["folded %"] == 0.0 and np.isnan(row["inverse consistency px"])


def test_regridding_switched_off_lets_a_large_deformation_fold():
    rows, cols = np.indices((32, 32), dtype=float) - 15.5
    disc = (np.hypot(rows, cols) < 8).astype(float)
    band = ((np.abs(rows) < 3) & (np.abs(cols) < 14)).astype(float)
    kept = cf.register_fluid(disc, band, "cat", n_iter=60)
    free = cf.register_fluid(disc, band, "cat", n_iter=60, regrid_threshold=0.0)
    assert kept.n_regrids > 0 and kept.history[:, 2].min() > 0
    assert free.n_regrids == 0 and free.history[:, 2].min() <= 0  # without regridding the map folds


@pytest.mark.parametrize("module", ["stencil", "solvers", "data", "registration"])
def test_docstring_examples_run(module):
    """The Examples sections of the entry points (fluid_stencil, solve_velocity, make_pair,
    register_fluid) are executed, so they cannot drift from the code."""
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(f"amdo_lab.cat_fluid.{module}"))
    assert result.attempted > 0 and result.failed == 0


def test_registration_images_pass_the_check_unchanged():
    from amdo_lab.cat_fluid.registration import check_registration_images

    template, study = make_rng(0).random((8, 8)), make_rng(1).random((8, 8))
    checked = check_registration_images(template, study)
    assert all(np.array_equal(a, b) for a, b in zip(checked, (template, study)))


def test_stencil_steps_follow_eqs_5_12_and_14_on_polynomial_fields():
    """The three steps inside fluid_stencil, each against a hand computation: the gradient (eq. 5) of
    the bilinear velocity (eq. 13), the stress (eq. 12) and the flux over the dual cell (eqs. 8-11, 14)."""
    gradient = np.array([[0.3, -1.2], [2.0, 0.7]])  # ∂v_i/∂x_j of a linear field: exact at every point
    linear = lambda i, j: gradient @ np.array([i, j], float) + np.array([5.0, -1.0])  # noqa: E731
    for point in ([0.25, 0.5], [-0.75, -0.25], [0.1, -0.9]):
        np.testing.assert_allclose(cf.bilinear_gradient(linear, point), gradient, atol=1e-12)
    product = lambda i, j: np.array([i * j, 0.0])  # noqa: E731  bilinear: ∂(x1 x2) = (x2, x1)
    np.testing.assert_allclose(cf.bilinear_gradient(product, [0.25, 0.75]), [[0.75, 0.25], [0, 0]])
    strain = (gradient + gradient.T) / 2
    np.testing.assert_allclose(cf.viscous_stress(gradient, 2.0, 3.0),
                               2.0 * np.trace(strain) * np.eye(2) + 2 * 3.0 * strain)
    for kind, field in QUADRATIC_FIELDS.items():
        corners = lambda i, j, field=field: np.array(field(float(i), float(j)))  # noqa: E731
        np.testing.assert_allclose(cf.dual_cell_force(corners, 2.0, 3.0), continuous_operator(kind, 2.0, 3.0),
                                   atol=1e-12)
    np.testing.assert_allclose(cf.dual_cell_force(linear, 2.0, 3.0), 0.0, atol=1e-12)


# --- rejections: one table -----------------------------------------------------------------
# tests/test_bad_input.py already spoils every argument of every public callable (NaN, inf or 1e308
# inside, empty, a wrong trailing axis, one axis more, a string, None, a bool, zero/negative/float counts,
# probabilities outside [0, 1], bad seeds) and checks that the error names the argument. This table holds
# what that test cannot see: the rules of the method (a 2-D complex, SOR's ω in (0, 2) and even grids,
# at least 2x2 pixels, images with structure, a centro-symmetric stencil, the grey-level bound), unknown
# names, pairs that must agree in shape, one axis too few, a third vector component, and the rng convention.
# A call's parameters without a default name the fixtures it needs.
@pytest.fixture(scope="module")
def small_images():
    rng = make_rng(6)
    return rng.random((16, 16)), rng.random((16, 16))


def _lopsided_stencil():
    """The derived stencil with neighbour (0, 1) changed alone: no longer centro-symmetric."""
    stencil = cf.fluid_stencil(LAM, MU)
    stencil[0, 2] += 1.0
    return stencil


def _too_bright(small_images):
    """The study with one pixel beyond dipy's single-precision margin (10 x MAX_GREY_LEVEL)."""
    huge = small_images[1].copy()
    huge[0, 0] = 10 * MAX_GREY_LEVEL
    return small_images[0], huge


REJECTIONS = [
    # --- the cubical complex (Sec. 2)
    reject("CubicalComplex 1-D shape", lambda: cf.CubicalComplex((4,)), ValueError, r"shape must be a pair \(H, W\)"),
    reject("CubicalComplex one row", lambda: cf.CubicalComplex((1, 4)), ValueError, r"shape\[0\] must be at least 2"),
    reject("boundary q 3", lambda: cf.CubicalComplex((3, 3)).boundary(3), ValueError, "q must be one of 1, 2"),
    reject("boundary q 1.0", lambda: cf.CubicalComplex((3, 3)).boundary(1.0), TypeError, "q must be an int"),
    # --- the stencil and its symbol (Sec. 4)
    reject("stencil_blocks boolean stencil", lambda: cf.stencil_blocks(np.ones((2, 18), bool)),
           TypeError, "stencil must be a numeric array"),
    reject("stencil_symbol not centro-symmetric", lambda: cf.stencil_symbol(_lopsided_stencil(), (8, 8)),
           ValueError, "centro-symmetric"),
    reject("stencil_symbol 1-D shape", lambda: cf.stencil_symbol(cf.printed_stencil(LAM, MU), (8,)),
           ValueError, r"shape must be a pair \(H, W\)"),
    reject("stencil_grid row 2", lambda: cf.stencil_grid(cf.fluid_stencil(LAM, MU), 2, 0), ValueError, "row must be one of 0, 1"),
    reject("stencil_at_origin NaN velocity", lambda: cf.stencil_at_origin(cf.fluid_stencil(), lambda a, b: (np.nan, 0.0)),
           ValueError, r"velocity\(0, 0\) must be finite"),
    reject("stencil_at_origin 3-vector velocity", lambda: cf.stencil_at_origin(cf.fluid_stencil(), lambda a, b: (a, b, 0.0)),
           ValueError, r"velocity\(0, 0\) must have shape \(2,\)"),
    reject("stencil_at_origin scalar velocity", lambda: cf.stencil_at_origin(cf.fluid_stencil(), lambda a, b: a),
           ValueError, r"velocity\(0, 0\) must have shape \(2,\)"),
    reject("solve_stencil_reference three components",
           lambda: cf.solve_stencil_reference(cf.fluid_stencil(), np.zeros((3, 4, 4))),
           ValueError, r"force must have shape \(2, n, n\)"),
    reject("sor_solve omega 2", lambda: cf.sor_solve(np.zeros((2, 8, 8)), LAM, MU, omega=2.0),
           ValueError, r"omega must be in \(0, 2\)"),
    reject("sor_solve ordering lexicographic", lambda: cf.sor_solve(np.zeros((2, 8, 8)), LAM, MU, ordering="lexicographic"),
           ValueError, "ordering"),
    reject("sor_solve odd grid", lambda: cf.sor_solve(np.zeros((2, 7, 8)), LAM, MU), ValueError, "force must have even H and W"),
    reject("solve_velocity method multigrid", lambda: cf.solve_velocity(np.zeros((2, 8, 8)), "multigrid"),
           ValueError, "method must be one of"),
    reject("symbol_eigenvalues rows and cols differ",
           lambda: cf.symbol_eigenvalues(cf.cat_symbol((16, 16), LAM, MU), [0, 1], [0]),
           ValueError, r"cols \(one per entry of rows\) must have shape"),
    reject("symbol_eigenvalues three rows", lambda: cf.symbol_eigenvalues(np.zeros((3, 2, 4, 3)), [0], [0]),
           ValueError, r"symbol must have shape \(2, 2, n, n\)"),
    # --- registration pieces: at least 2x2 pixels, pairs that cover the same pixels
    reject("displacement_jacobian one row", lambda: cf.displacement_jacobian(np.zeros((2, 1, 5))),
           ValueError, "displacement's smaller image side \\(pixels\\) must be at least 2"),
    reject("jacobian_determinant one column", lambda: cf.jacobian_determinant(np.zeros((2, 5, 1))),
           ValueError, "displacement's smaller image side \\(pixels\\) must be at least 2"),
    reject("material_update one row", lambda: cf.material_update(np.zeros((2, 1, 5)), np.zeros((2, 1, 5)), 0.5),
           ValueError, "displacement's smaller image side \\(pixels\\) must be at least 2"),
    reject("material_update velocity and displacement differ",
           lambda: cf.material_update(np.zeros((2, 8, 8)), np.zeros((2, 8, 7)), 0.5),
           ValueError, r"velocity \(on the pixels of displacement\) must have shape \(2, 8, 8\)"),
    reject("external_force one row", lambda: cf.external_force(np.ones((1, 5)), np.ones((1, 5))),
           ValueError, "deformed_template's smaller image side \\(pixels\\) must be at least 2"),
    reject("external_force images differ", lambda: cf.external_force(np.zeros((8, 8)), np.zeros((8, 7))),
           ValueError, "deformed_template and study must have the same shape"),
    reject("warp_image displacement and image differ", lambda: cf.warp_image(np.zeros((8, 8)), np.zeros((2, 8, 9))),
           ValueError, r"displacement \(on the pixels of image\) must have shape \(2, 8, 8\)"),
    reject("grey_level_difference empty mask",
           lambda: cf.grey_level_difference(np.zeros((4, 4)), np.zeros((4, 4)), np.zeros((4, 4), bool)),
           ValueError, "mask must select at least one pixel"),
    *[case for measure in (cf.displacement_rmse, cf.inverse_consistency_error) for case in (
        reject(f"{measure.__name__} mask of another size", lambda measure=measure: measure(
            np.zeros((2, 4, 4)), np.ones((2, 4, 4)), np.ones((3, 3), bool)), ValueError, r"mask must have shape \(4, 4\)"),
        reject(f"{measure.__name__} empty mask", lambda measure=measure: measure(
            np.zeros((2, 4, 4)), np.ones((2, 4, 4)), np.zeros((4, 4), bool)), ValueError, "at least one"),
    )],
    # --- register_fluid: images of the same shape with structure, the named methods, SOR's ω
    reject("register_fluid images differ", lambda small_images: cf.register_fluid(
        small_images[0], small_images[1][:, :-2]), ValueError,
        r"study \(same shape as template\) must have shape"),
    reject("register_fluid flat study", lambda small_images: cf.register_fluid(
        small_images[0], small_images[1].ravel()), ValueError,
        r"study \(same shape as template\) must have shape"),
    reject("register_fluid constant template", lambda small_images: cf.register_fluid(
        np.full_like(small_images[0], 0.3), small_images[1]), ValueError, "template is constant"),
    reject("register_fluid constant study", lambda small_images: cf.register_fluid(
        small_images[0], np.zeros_like(small_images[1])), ValueError, "study is constant"),
    reject("register_fluid method demons", lambda small_images: cf.register_fluid(*small_images, method="demons"),
           ValueError, "method must be one of"),
    reject("register_fluid sor_omega 2.5", lambda small_images: cf.register_fluid(*small_images, sor_omega=2.5),
           ValueError, r"sor_omega must be in \(0, 2\)"),
    *[reject(f"{function.__name__} study beyond the grey-level bound",
             lambda small_images, function=function: function(*_too_bright(small_images)),
             ValueError, r"study \(same shape as template\) must be at most") for function in
      (check_registration_images, cf.register_fluid, cf.register_dipy)],
    reject("check_registration_images images differ", lambda small_images: check_registration_images(
        small_images[0], small_images[1][:, :6]), ValueError, "same shape"),
    reject("register_dipy no levels", lambda small_images: cf.register_dipy(*small_images, level_iters=()),
           ValueError, "level_iters must not be empty"),
    # --- data and tables
    reject("make_pair D", lambda: cf.make_pair("D", rng=0), ValueError, "name must be one of 'A', 'B', 'C'"),
    reject("load_dipy_image t2_axial", lambda: cf.load_dipy_image("t2_axial"), ValueError, "name must be one of"),
    reject("grey_level_table deformed pair not in pairs", lambda: cf.grey_level_table(
        {"C": cf.RegistrationPair("C", np.ones((4, 4)), np.ones((4, 4)), np.zeros((2, 4, 4)), np.ones((4, 4), bool))},
        {"A": {"none": np.ones((4, 4))}}), ValueError, "deformed"),
    # --- the rng convention: keyword-only, no default, errors naming rng
    *[case for name, draw in (("make_pair", lambda *a, **kw: cf.make_pair("C", *a, **kw)),) for case in (
        reject(f"{name} without rng", lambda draw=draw: draw(), TypeError, "rng"),  # the caller chooses every draw
        reject(f"{name} rng -1", lambda draw=draw: draw(rng=-1), ValueError, "rng"),
        reject(f"{name} rng 1.5", lambda draw=draw: draw(rng=1.5), TypeError, "rng"),
        reject(f"{name} positional rng", lambda draw=draw: draw(0), TypeError, "positional argument"),
    )],
]


@pytest.mark.parametrize(("call", "error", "message"), REJECTIONS)
def test_rejections(request, call, error, message):
    check_rejection(request, call, error, message)


# --- known answers at the bounds: a finite result is not enough, it must be the right one -----------
# The bad-input test checks that a huge input is refused or gives finite output; these operations have
# an answer known in closed form, checked at the largest magnitudes their docstrings accept.
_BIG = 1e100  # MAX_FIELD: the largest displacement, velocity or force component accepted
_SHIFT = np.full((2, 8, 8), _BIG)  # a uniform displacement: no gradient
_RAMP = np.stack([0.5 * np.indices((8, 8))[0], np.zeros((8, 8))])  # u_1 = x1 / 2: det(I - ∇u) = 1/2
_IMAGE = make_rng(3).random((8, 8))

KNOWN_ANSWERS = {
    "uniform shift has no area change": (lambda: cf.jacobian_determinant(_SHIFT), np.ones((8, 8))),
    "a ramp halves the area": (lambda: cf.jacobian_determinant(_RAMP), np.full((8, 8), 0.5)),
    "zero displacement leaves the image": (lambda: cf.warp_image(_IMAGE, np.zeros((2, 8, 8))), _IMAGE),
    "composing with zero": (lambda: _compose(_SHIFT, np.zeros((2, 8, 8))), _SHIFT),
    "zero velocity leaves u": (lambda: cf.material_update(_SHIFT, np.zeros((2, 8, 8)), 0.5), _SHIFT),
    "from rest, u = Δt v": (lambda: cf.material_update(np.zeros((2, 8, 8)), _SHIFT, 0.5), 0.5 * _SHIFT),
    "an estimate equal to the truth": (lambda: cf.displacement_rmse(_SHIFT, _SHIFT), 0.0),
    "twice the truth misses by its length": (lambda: cf.displacement_rmse(2 * _SHIFT, _SHIFT), np.sqrt(2) * _BIG),
    "an image against itself": (lambda: cf.grey_level_difference(_IMAGE, _IMAGE, scale=255.0), (0.0, 0.0)),
    "constant velocity feels no force": (
        lambda: cf.apply_stencil(cf.fluid_stencil(1e150, 1e150), np.ones((2, 8, 8))) / 1e150, np.zeros((2, 8, 8))),
    "the stencil at the largest moduli is consistent": (
        lambda: max(cf.consistency_errors(cf.fluid_stencil(1e150, 1e150), 1e150, 1e150).values()) / 1e150, 0.0),
    "stress of a pure shear": (lambda: cf.viscous_stress([[0.0, _BIG], [0.0, 0.0]], 0.0, 1.0),
                               np.array([[0.0, _BIG], [_BIG, 0.0]])),
}


@pytest.mark.parametrize("name", KNOWN_ANSWERS)
def test_known_answers_hold_at_the_bounds(name):
    call, expected = KNOWN_ANSWERS[name]
    np.testing.assert_allclose(call(), expected, rtol=1e-12, atol=1e-12)


def test_the_cat_operator_is_negative_semidefinite_and_zero_at_zero_frequency():
    symbol = cf.cat_symbol((8, 8), 1e150, 1e150) / 1e150  # the largest moduli accepted
    rows, cols = np.indices((8, 5)).reshape(2, -1)
    eigenvalues = cf.symbol_eigenvalues(symbol, rows, cols)
    assert np.all(eigenvalues <= 1e-12) and np.abs(eigenvalues[0]).max() < 1e-12
