"""Degenerate valid input and the rules of the checks: defined statistics, messages that name the argument at fault.

Each test pins one case the public-API fuzz found outside the spoiled calls of ``test_bad_input``:
statistics of identical distributions, messages that led with the wrong argument, record fields
not checked by the class documented to check them, and the validators' own rule parameters.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from amdo_lab import common, cue_fusion_pf as cf, ear_biometrics as eb, path_relinking_pf as pr


# --- d', AUC and the ratio of genuine_impostor_separation on degenerate input

@pytest.mark.parametrize("distances", [np.zeros((2, 2)), np.full((3, 3), 2.5)])
def test_identical_distributions_separate_by_nothing(distances):
    n = len(distances)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way
        separation = eb.genuine_impostor_separation(distances, list(range(n)), list(range(n)))
    assert separation.d_prime == 0.0 and separation.auc == 0.5 and separation.ratio == 1.0


def test_zero_spreads_with_a_gap_give_signed_infinite_d_prime():
    apart = np.array([[0.0, 1.0], [1.0, 0.0]])      # every genuine 0, every impostor 1
    assert eb.genuine_impostor_separation(apart, [0, 1], [0, 1]).d_prime == np.inf
    inverted = np.array([[1.0, 0.0], [0.0, 1.0]])   # impostors closer than the genuine: a negative gap
    separation = eb.genuine_impostor_separation(inverted, [0, 1], [0, 1])
    assert separation.d_prime == -np.inf and separation.auc == 0.0 and separation.ratio == np.inf


def test_a_zero_impostor_median_gives_a_defined_ratio():
    distances = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])  # impostor median 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        separation = eb.genuine_impostor_separation(distances, [0, 1, 2], [0, 1, 2])
    assert separation.ratio == np.inf and np.isfinite(separation.d_prime)


def test_the_ordinary_case_is_unchanged():
    distances = np.array([[0.1, 0.9, 0.8], [0.7, 0.2, 0.9], [0.8, 0.6, 0.3]])
    separation = eb.genuine_impostor_separation(distances, [0, 1, 2], [0, 1, 2])
    genuine, impostor = np.array([0.1, 0.2, 0.3]), np.array([0.9, 0.8, 0.7, 0.9, 0.8, 0.6])
    expected = (impostor.mean() - genuine.mean()) / np.sqrt(0.5 * (genuine.var() + impostor.var()))
    assert separation.d_prime == pytest.approx(expected)
    assert separation.ratio == pytest.approx(np.median(genuine) / np.median(impostor))


# --- messages that lead with the argument at fault

def test_joint_errors_px_names_a_single_pose_as_poses():
    model = pr.BodyModel.upper_body()
    with pytest.raises(ValueError, match=r"^poses must have shape \(T, 10\), got \(10,\)"):
        pr.joint_errors_px(model, poses=np.zeros(10), truth=np.zeros((3, 10)))
    with pytest.raises(ValueError, match=r"^truth must have shape"):
        pr.joint_errors_px(model, poses=np.zeros((3, 10)), truth=np.zeros((2, 10)))


@pytest.mark.parametrize(("angles", "lengths"), [(np.zeros(2), np.ones(3)), (np.zeros(3), np.ones(2))])
def test_planar_chain_names_both_sides_of_a_mismatch(angles, lengths):
    with pytest.raises(ValueError, match=rf"^angles and lengths disagree: angles ends in {angles.size} angles .*"
                                         rf"lengths has {lengths.size} links"):
        common.planar_chain(angles, lengths)


@pytest.mark.parametrize(("first", "second"), [(np.zeros((1, 4, 2)), np.zeros((4, 2))),
                                               (np.zeros((4, 2)), np.zeros((2, 4, 2)))])
def test_box_iou_names_both_sides_of_a_mismatch(first, second):
    with pytest.raises(ValueError, match=rf"^first and second disagree: first has shape "
                                         rf"\({', '.join(map(str, first.shape))}"):
        cf.box_iou(first, second)


def test_box_iou_checks_second_on_its_own_first():
    with pytest.raises(ValueError, match=r"^second must have shape \(J, 2\) or \(T, J, 2\)"):
        cf.box_iou(np.zeros((4, 2)), np.zeros((4, 3)))


# --- the Limb fields, checked by BodyModel

@pytest.mark.parametrize(("field", "value", "error", "message"), [
    ("grey", None, TypeError, r"limbs\[2\]\.grey must be an int"),
    ("grey", 10**9, ValueError, r"limbs\[2\]\.grey must be at most 255"),
    ("grey", -1, ValueError, r"limbs\[2\]\.grey must be at least 0"),
    ("name", None, TypeError, r"limbs\[2\]\.name must be a non-empty str"),
    ("name", "", TypeError, r"limbs\[2\]\.name must be a non-empty str"),
    ("size", None, TypeError, r"limbs\[2\]\.size"),
    ("size", (1.0, np.nan, 2.0), ValueError, r"limbs\[2\]\.size"),
    ("position", "x", TypeError, r"limbs\[2\]\.position"),
    ("position", (1.0, 2.0, 3.0), ValueError, r"limbs\[2\]\.position"),
    ("father", 1.0, TypeError, r"limbs\[2\]\.father must be an int"),
    ("shape", "Q", ValueError, r"limbs\[2\]\.shape must be one of 'T', 'E'"),
])
def test_body_model_checks_every_limb_field(field, value, error, message):
    limbs = list(pr.BodyModel.upper_body().limbs)
    limbs[2] = dataclasses.replace(limbs[2], **{field: value})
    with pytest.raises(error, match=message):
        pr.BodyModel(limbs)


def test_the_paper_body_passes_its_limb_checks():
    model = pr.BodyModel.upper_body()
    assert pr.BodyModel(list(model.limbs)).n_pose == model.n_pose


# --- the validators' rule parameters

def test_check_choice_refuses_a_string_as_choices():
    with pytest.raises(TypeError, match="choices must be a collection of options, not a string"):
        common.check_choice("a", "metric", "abc")
    assert common.check_choice("a", "metric", ("a", "b")) == "a"


@pytest.mark.parametrize("dim", [2.5, 0, True, "2"])
def test_as_points_refuses_a_dim_that_is_not_a_positive_int(dim):
    with pytest.raises(TypeError, match="dim must be a positive int"):
        common.as_points(np.zeros((3, 2)), "points", dim=dim)


def test_kernel_histogram_is_float_on_and_off_the_frame():
    frame = np.zeros((20, 20, 3), np.uint8)
    on = cf.kernel_histogram(frame, [10.0, 10.0, 5.0, 5.0, 0.0], 8)
    off = cf.kernel_histogram(frame, [100.0, 100.0, 5.0, 5.0, 0.0], 8)
    assert on.dtype == off.dtype == np.float64
    assert on.sum() == pytest.approx(1.0) and not off.any()


# --- input records edited with dataclasses.replace are checked where a public function receives them

def _valid(subpackage: str, name: str) -> dict:
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from test_bad_input import table

    return table(subpackage).cases()[name].valid


def test_edited_records_are_refused_by_their_field():
    sequence = _valid("path_relinking_pf", "check_sequence")["sequence"]
    with pytest.raises(ValueError, match=r"sequence\.background must be finite|sequence\.background .*NaN"):
        pr.check_sequence(dataclasses.replace(sequence, background=np.full(sequence.background.shape, np.nan)))
    with pytest.raises(TypeError, match=r"sequence\.model must be a BodyModel"):
        pr.check_sequence(dataclasses.replace(sequence, model=None))
    observation = _valid("path_relinking_pf", "ObservationModel")
    measurement, model = observation["measurement"], observation["model"]
    with pytest.raises(TypeError, match=r"measurement\.B must be a 2-D bool silhouette"):
        pr.ObservationModel(dataclasses.replace(measurement, B=np.full(measurement.B.shape, np.nan)), model)
    with pytest.raises(ValueError, match=r"measurement\.E"):
        pr.ObservationModel(dataclasses.replace(measurement, E=measurement.E + 2.0), model)
    from amdo_lab import modal_matching as mm

    step = _valid("modal_matching", "paper_pair")["sequence"]
    with pytest.raises(ValueError, match=r"sequence\.mm_per_px"):
        mm.paper_pair(dataclasses.replace(step, mm_per_px=np.nan), "isobars")
    enrol = _valid("ear_biometrics", "EarMatcher.enroll_template")
    with pytest.raises(TypeError, match=r"template\.circles"):
        eb.EarMatcher().enroll_template(5, dataclasses.replace(enrol["template"], circles=None))
