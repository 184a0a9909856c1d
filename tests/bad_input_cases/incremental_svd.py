"""Bad-input table of ``amdo_lab.incremental_svd``: a valid call and the kind of each argument.

The valid inputs are tiny: a 6-pixel model of rank 2 learnt from 4 frames, 40 x 41 faces.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "SvdState": "a result record (a tuple with names), built by the update functions from checked input",
    "TalkingFace": "a result record, built by make_talking_face from checked input",
    "TrainingResult": "a result record, built by train_on_the_fly and train_non_causal from checked input",
    "IncrementalSVD.memory_bytes": "takes no argument",
}

#: None means "no cap" / "no threshold" for these parameters.
_NONE_OK = frozenset({("max_rank", "None"), ("tol", "None")})


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.incremental_svd``, by name."""
    from amdo_lab import incremental_svd as isvd

    frames = np.random.default_rng(0).normal(size=(4, 6))
    fitted = isvd.IncrementalSVD(max_rank=2).partial_fit(frames)
    U, s, V, mean = fitted.state
    new = np.random.default_rng(1).normal(size=(6, 2))
    arrays = {"U": "array", "s": "array", "V": "array"}
    any_count = frozenset({("I", "a wrong trailing axis")})  # three new columns instead of two are fine

    track_face = isvd.make_talking_face(3, rng=0, size=(40, 41), motion="similarity")
    track_valid = {"frames": track_face.frames, "masks": track_face.masks, "init": np.zeros(4), "max_rank": 2}
    track_kinds = {"frames": "array", "masks": "object", "init": "array", "max_rank": "count"}

    def method(name):
        return lambda **kwargs: getattr(fitted, name)(**kwargs)

    def learner(max_rank, tol, mean, X):
        return isvd.IncrementalSVD(max_rank=max_rank, tol=tol, mean=mean).partial_fit(X)

    return {
        "IncrementalSVD": Case(learner, {"max_rank": 2, "tol": 0.0, "mean": "paper", "X": frames},
                               {"max_rank": "count", "tol": "non_negative", "mean": "name", "X": "array"},
                               accept=_NONE_OK | {("X", "a wrong trailing axis")}),  # a first fit sets p
        "IncrementalSVD.partial_fit": Case(method("partial_fit"), {"X": frames[:1]}, {"X": "array"}),
        "IncrementalSVD.transform": Case(method("transform"), {"X": frames}, {"X": "array"}),
        "IncrementalSVD.reconstruct": Case(method("reconstruct"), {"X": frames}, {"X": "array"}),
        "brand_update": Case(isvd.brand_update, {"U": U, "s": s, "V": V, "I": new},
                             {**arrays, "I": "array"}, accept=any_count),
        "update_with_mean": Case(isvd.update_with_mean, {"U": U, "s": s, "V": V, "mean": mean, "I": new,
                                                         "fast": True},
                                 {**arrays, "mean": "array", "I": "array", "fast": "flag"}, accept=any_count),
        "extract_mean": Case(isvd.extract_mean, {"U": U, "s": s, "V": V, "fast": False},
                             {**arrays, "fast": "flag"}),
        "ross_update": Case(isvd.ross_update, {"U": U, "s": s, "mean": mean, "n_seen": 4, "I": new},
                            {"U": "array", "s": "array", "mean": "array", "n_seen": "count", "I": "array"},
                            accept=any_count | {("n_seen", "zero")}),
        "tau_schedule": Case(isvd.tau_schedule, {"t": 3}, {"t": "count"}, accept=frozenset({("t", "zero")})),
        "noise_edge": Case(isvd.noise_edge, {"sigma": 0.01, "p": 100, "q": 25},
                           {"sigma": "positive", "p": "count", "q": "count"}),
        "make_talking_face": Case(isvd.make_talking_face, {"n_frames": 2, "rng": 0, "size": (40, 41), "noise": 0.01,
                                                           "motion": "similarity"},
                                  {"n_frames": "count", "rng": "seed", "size": "object", "noise": "non_negative",
                                   "motion": "name"}),
        "similarity_points": Case(isvd.similarity_points, {"params": np.zeros(4), "points": np.ones((3, 2)),
                                                           "size": (40, 41)},
                                  {"params": "array", "points": "array", "size": "object"},
                                  accept=frozenset({("params", "one more axis")})),  # (1, 4): one placement
        "corner_error_px": Case(isvd.corner_error_px, {"params": np.zeros((2, 4)), "truth": np.ones((2, 4)),
                                                       "size": (40, 41)},
                                {"params": "array", "truth": "array", "size": "object"}),
        "corner_error_less_offset_px": Case(isvd.corner_error_less_offset_px,
                                            {"params": np.zeros((2, 4)), "truth": np.ones((2, 4)), "size": (40, 41)},
                                            {"params": "array", "truth": "array", "size": "object"}),
        "train_on_the_fly": Case(isvd.train_on_the_fly, {**track_valid, "tau": "paper", "noise": 0.01,
                                                         "learn_at": track_face.truth},
                                 {**track_kinds, "tau": "name", "noise": "positive", "learn_at": "array"},
                                 accept=frozenset({("learn_at", "None"),  # None: learn at the aligner's own
                                                   ("noise", "None")})),  # None: estimated from the first frame
        "train_non_causal": Case(isvd.train_non_causal, {**track_valid, "tau": "paper", "noise": 0.01, "rounds": 1},
                                 {**track_kinds, "tau": "name", "noise": "positive", "rounds": "count"},
                                 accept=frozenset({("rounds", "zero"), ("noise", "None")})),
        "estimate_noise": Case(isvd.estimate_noise, {"image": track_face.frames[0]}, {"image": "array"},
                               accept=frozenset({("image", "a wrong trailing axis")})),  # any size; zeros: sigma 0
        "render_faces": Case(isvd.render_faces, {"latent": [[0.5, 0.0, 0.0, 0.0]], "size": (40, 41)},
                             {"latent": "array", "size": "object"}),
        "psnr_db": Case(isvd.psnr_db, {"estimate": frames, "clean": frames + 0.01},
                        {"estimate": "array", "clean": "array"}),
    }
