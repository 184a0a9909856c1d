"""Every public record and trained model survives pickle, copy.copy and copy.deepcopy, equal afterwards.

A user saves a trained model (the on-the-fly SVD of chapter 7 is the point of its method) or a
result record, and loads it later. The records come from the bad-input tables
(``tests/bad_input_cases/``): the valid inputs of every tabled call, the objects its bound methods
and closures hold, and the results of a fixed list of cheap valid calls, so a record type a table
uses cannot escape. A coverage test checks that every class a subpackage exports is among them.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import inspect
import pickle
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the tables: tests/bad_input_cases/

from test_bad_input import SUBPACKAGES, table  # noqa: E402

#: Valid calls whose results hold record types that no table input holds (subpackage, tabled name).
RESULT_CALLS = (
    ("active_contours", "HamStudy.muscle"), ("active_contours", "greedy_snake"),
    ("cat_fluid", "CubicalComplex"), ("cat_fluid", "register_dipy"), ("cat_fluid", "register_fluid(method='sor')"),
    ("common", "procrustes_align"), ("common", "paired_comparison"), ("common", "rate_interval"),
    ("cue_fusion_pf", "ARDynamics"), ("cue_fusion_pf", "calibrate_sigma"), ("cue_fusion_pf", "EdgeLikelihood"),
    ("cue_fusion_pf", "StructureLikelihood"), ("cue_fusion_pf", "track_camshift"),
    ("ear_biometrics", "closed_set"), ("ear_biometrics", "open_set_rates"),
    ("ear_biometrics", "genuine_impostor_separation"), ("ear_biometrics", "EarMatcher.identify_template"),
    ("ear_biometrics", "HogNearestNeighbour.fit"), ("ear_biometrics", "make_ear_database"),
    ("em_articulated", "make_registration_problem"), ("em_articulated", "make_skin_texture"),
    ("em_articulated", "make_tracking_sequence"), ("em_articulated", "refine_digits"),
    ("em_articulated", "register_em"), ("em_articulated", "run_registration_trials"), ("em_articulated", "objective_check"),
    ("em_articulated", "register_softassign"), ("em_articulated", "fit_surface"), ("em_articulated", "track"),
    ("face_glmm", "fit_naive_logistic"), ("face_glmm", "experiment_draws"), ("face_glmm", "pca_basis"),
    ("face_glmm", "PcaLda.fit"), ("face_glmm", "make_face_population"), ("face_glmm", "recovery_study"),
    ("incremental_svd", "make_talking_face"), ("incremental_svd", "IncrementalSVD"),
    ("incremental_svd", "brand_update"), ("incremental_svd", "train_on_the_fly"),
    ("incremental_svd", "train_non_causal"),
    ("modal_matching", "axial_element"), ("modal_matching", "match_coordinates"),
    ("path_relinking_pf", "track_pfilter"),
    ("pdm_mixtures", "NearestProcrustesMeanClassifier.fit"), ("pdm_mixtures", "SingleCartesianPDMClassifier.fit"),
    ("pdm_mixtures", "SklearnGMMClassifier.fit"), ("pdm_mixtures", "fit_gaussian_mixture"),
    ("pdm_mixtures", "make_pose_dataset"), ("pdm_mixtures", "ArticulatedShapeRecogniser.iterative_alignment"),
    ("pdm_mixtures", "ArticulatedShapeRecogniser.fit"), ("pdm_mixtures", "ArticulatedShapeRecogniser.recognise"),
    ("pdm_mixtures", "ArticulatedShapeRecogniser.score_components"),
)

#: The trained models of chapters 2, 4, 5 and 7: each must be among the records tested.
TRAINED_MODELS = (
    "amdo_lab.pdm_mixtures.recogniser.ArticulatedShapeRecogniser",
    "amdo_lab.pdm_mixtures.baselines.SklearnGMMClassifier",
    "amdo_lab.ear_biometrics.matcher.EarMatcher",
    "amdo_lab.ear_biometrics.peers.HogNearestNeighbour",
    "amdo_lab.face_glmm.glmm.GlmmResult",
    "amdo_lab.face_glmm.pcalda.PcaLda",
    "amdo_lab.incremental_svd.svd_update.IncrementalSVD",
    "amdo_lab.incremental_svd.svd_update.SvdState",
    "amdo_lab.incremental_svd.tracking.TrainingResult",
)


def _type_name(value: object) -> str:
    kind = type(value)
    return f"{kind.__module__}.{kind.__qualname__}"


def _collect(value: object, found: dict, depth: int = 0) -> None:
    """Record the first instance of every ``amdo_lab`` type in ``value`` and the containers it holds."""
    if depth > 3:
        return
    if type(value).__module__.startswith("amdo_lab"):
        found.setdefault(_type_name(value), value)
    if isinstance(value, (list, tuple)):
        for item in list(value)[:3]:
            _collect(item, found, depth + 1)
    elif isinstance(value, dict):
        for item in list(value.values())[:5]:
            _collect(item, found, depth + 1)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for item in dataclasses.fields(value):
            _collect(getattr(value, item.name), found, depth + 1)


def _held_by(function: object) -> list[object]:
    """The objects a tabled callable holds: a bound method's instance, a closure's variables."""
    held = [getattr(function, "__self__", None)]
    if inspect.isfunction(function):
        held += list(inspect.getclosurevars(function).nonlocals.values())
    return [value for value in held if value is not None]


@pytest.fixture(scope="module")
def records() -> dict[str, object]:
    found: dict[str, object] = {}
    wanted = set(RESULT_CALLS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for subpackage in SUBPACKAGES:
            for name, case in table(subpackage).cases().items():
                for value in [*case.valid.values(), *_held_by(case.function)]:
                    _collect(value, found)
                if (subpackage, name) in wanted:
                    _collect(case.function(**case.valid), found)
    from amdo_lab.active_contours import SnakeWeights  # a settings record no table holds

    _collect(SnakeWeights(0.5, 1.0, 1.2), found)
    return found


def same(first: object, second: object, depth: int = 0) -> bool:
    """Whether two objects hold equal data: arrays by value (NaN equal to NaN), records field by field."""
    if type(first) is not type(second):
        return False
    if depth > 12:
        return True
    if isinstance(first, np.ndarray):
        return (first.shape == second.shape and first.dtype == second.dtype
                and bool(np.array_equal(first, second, equal_nan=first.dtype.kind in "fc")))
    if isinstance(first, (float, np.floating)):
        return bool(first == second or (np.isnan(first) and np.isnan(second)))
    if isinstance(first, np.random.Generator):
        return first.bit_generator.state == second.bit_generator.state
    if hasattr(first, "equals") and hasattr(first, "dtypes"):  # pandas
        return bool(first.equals(second))
    if isinstance(first, (list, tuple)):
        return len(first) == len(second) and all(same(a, b, depth + 1) for a, b in zip(first, second))
    if isinstance(first, dict):
        return first.keys() == second.keys() and all(same(first[k], second[k], depth + 1) for k in first)
    if dataclasses.is_dataclass(first):
        return all(same(getattr(first, f.name), getattr(second, f.name), depth + 1)
                   for f in dataclasses.fields(first))
    if hasattr(first, "__dict__") and not callable(first) or type(first).__module__.startswith("amdo_lab"):
        slots = [s for klass in type(first).__mro__ for s in getattr(klass, "__slots__", ())]
        state = [vars(first) if hasattr(first, "__dict__") else {}, {s: getattr(first, s, None) for s in slots}]
        other = [vars(second) if hasattr(second, "__dict__") else {}, {s: getattr(second, s, None) for s in slots}]
        return same(state, other, depth + 1)
    try:
        return bool(first == second)
    except Exception:  # noqa: BLE001 - an object without a usable == compares by its representation
        return repr(first) == repr(second)


COPIES = {"pickle": lambda value: pickle.loads(pickle.dumps(value)), "copy.copy": copy.copy,
          "copy.deepcopy": copy.deepcopy}


def test_every_record_round_trips_equal(records):
    broken = []
    for name, value in sorted(records.items()):
        for how, duplicate in COPIES.items():
            try:
                again = duplicate(value)
            except Exception as error:  # noqa: BLE001 - reported with the record's name
                broken.append(f"{name} through {how}: {type(error).__name__}: {error}")
                continue
            if not same(value, again):
                broken.append(f"{name} through {how}: not equal afterwards")
    assert not broken, f"{len(broken)} of {3 * len(records)} round trips failed:\n" + "\n".join(broken)


def test_every_exported_class_and_trained_model_is_tested(records):
    exported = set()
    for subpackage in SUBPACKAGES:
        module = importlib.import_module(f"amdo_lab.{subpackage}")
        for name in module.__all__:
            value = getattr(module, name)
            if inspect.isclass(value) and value.__module__.startswith("amdo_lab"):
                exported.add(f"{value.__module__}.{value.__qualname__}")
    missing = sorted((exported | set(TRAINED_MODELS)) - set(records))
    assert not missing, f"no instance of {missing} in the tables' valid calls"
    assert len(records) >= 90


def test_a_saved_svd_model_tracks_the_next_frame_identically():
    from amdo_lab import incremental_svd as isvd
    from amdo_lab.incremental_svd.tracking import _align_frame

    valid = table("incremental_svd").cases()["train_on_the_fly"].valid
    frames = valid["frames"]
    trained = isvd.train_on_the_fly(frames[:-1], valid["masks"], valid["init"], max_rank=valid["max_rank"],
                                    tau="paper")
    loaded = pickle.loads(pickle.dumps(trained))
    assert isinstance(loaded.models[next(iter(loaded.models))], isvd.SvdState)
    placed = [_align_frame(frames[-1], valid["masks"], models, trained.params[-1])
              for models in (trained.models, loaded.models, copy.deepcopy(trained.models))]
    assert np.array_equal(placed[0], placed[1]) and np.array_equal(placed[0], placed[2])
    # a learner saved mid-stream goes on learning as the one that was not saved; not bit for bit: its U_ and V_
    # are views the save makes contiguous, and BLAS sums a contiguous array in another order (round-off only)
    learner = isvd.IncrementalSVD(max_rank=3).partial_fit(frames[:2].reshape(2, -1))
    saved = pickle.loads(pickle.dumps(learner))
    assert same(learner, saved)
    for model in (learner, saved):
        model.partial_fit(frames[-1:].reshape(1, -1))
    assert all(np.allclose(a, b, rtol=1e-12, atol=1e-12) for a, b in zip(learner.state, saved.state) if a is not None)
