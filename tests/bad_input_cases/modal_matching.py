"""Bad-input table of ``amdo_lab.modal_matching``: a valid call and the kind of each argument.

The valid inputs are small: outlines of 9 and 8 nodes, a 15-frame pressure sequence.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "GaussianElement": "a result record, built by gaussian_element from checked input",
    "AxialElement": "a result record, built by axial_element from checked input",
    "ModalBasis": "a result record, built by modal_analysis from a checked element",
    "MatchResult": "a result record, built by the matching functions from checked input",
    "ObjectPair": "a result record, built by paper_pair from a checked sequence",
    "PedobarographySequence": "a result record, built by make_pedobarography_sequence from checked input",
    "ModalBasis.rigid_cosines": "takes no argument",
}

#: A node set of another dimension is a valid object of its own (a 3-D outline).
_ANY_D = frozenset({("nodes", "a wrong trailing axis")})
#: ADCom looks for neighbours within each object: X1 and X2 need not share D.
_EACH_OWN_D = frozenset({("X1", "a wrong trailing axis"), ("X2", "a wrong trailing axis")})


def _outline(n: int, seed: int = 0) -> np.ndarray:
    angle = np.linspace(0, 2 * np.pi, n, endpoint=False)
    noise = np.random.default_rng(seed).normal(0, 0.2, (n, 2))
    return np.c_[13 * np.cos(angle), 10 * np.sin(angle) * (1 + 0.2 * np.cos(3 * angle))] + noise


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.modal_matching``, by name."""
    from amdo_lab import modal_matching as mm

    X1, X2 = _outline(9), _outline(8, 1)
    model = mm.gaussian_element(X1, sigma=mm.mean_spacing(X1))
    modes1, modes2 = mm.modal_analysis(model), mm.modal_analysis(mm.gaussian_element(X2, sigma=mm.mean_spacing(X1)))
    Z = mm.affinity_matrix(modes1, modes2, n_modes=4)
    pairs = mm.global_search(Z)
    ring = np.array([(i, (i + step) % len(X1)) for step in (1, 2) for i in range(len(X1))])
    step = mm.make_pedobarography_sequence(rng=0)
    pair = mm.ObjectPair(X1, X2, X1)
    objects = {"X1": X1, "X2": X2}
    object_kinds = {"X1": "array", "X2": "array"}
    rectangular = frozenset({("Z", "a wrong trailing axis")})  # another m2 is another valid problem

    def method(owner, name):
        return lambda **kwargs: getattr(owner, name)(**kwargs)

    return {
        "gaussian_element": Case(mm.gaussian_element, {"nodes": X1, "sigma": 3.0, "young": 1.0, "poisson": 0.3,
                                                       "density": 1.0, "rigid": "exact"},
                                 {"nodes": "array", "sigma": "positive", "young": "positive", "poisson": "real",
                                  "density": "positive", "rigid": "name"}, accept=_ANY_D | {("poisson", "zero")}),
        "axial_element": Case(mm.axial_element, {"nodes": X1, "edges": ring, "young": 1.0, "density": 1.0},
                              {"nodes": "array", "edges": "array", "young": "positive", "density": "positive"},
                              accept=_ANY_D),
        "mean_spacing": Case(mm.mean_spacing, {"nodes": X1}, {"nodes": "array"}, accept=_ANY_D),
        "modal_analysis": Case(mm.modal_analysis, {"model": model}, {"model": "object"}),
        "ModalBasis.node_vectors": Case(method(modes1, "node_vectors"), {"n_modes": 3}, {"n_modes": "count"}),
        "mode_features": Case(mm.mode_features, {"modes1": modes1, "modes2": modes2, "n_modes": 4,
                                                 "align": "sign"},
                              {"modes1": "object", "modes2": "object", "n_modes": "count", "align": "name"}),
        "affinity_matrix": Case(mm.affinity_matrix, {"modes1": modes1, "modes2": modes2, "n_modes": 4,
                                                     "align": "procrustes"},
                                {"modes1": "object", "modes2": "object", "n_modes": "count", "align": "name"}),
        "procrustes_alignment": Case(mm.procrustes_alignment, {"modes1": modes1, "modes2": modes2, "n_modes": 4},
                                     {"modes1": "object", "modes2": "object", "n_modes": "count"}),
        "local_search": Case(mm.local_search, {"Z": Z}, {"Z": "array"}, accept=rectangular),
        "global_search": Case(mm.global_search, {"Z": Z, "pad": True}, {"Z": "array", "pad": "flag"},
                              accept=rectangular),
        "adcom": Case(mm.adcom, {"Z": Z, "pairs": pairs, **objects}, {"Z": "array", "pairs": "array", **object_kinds},
                      accept=rectangular | _EACH_OWN_D),
        "match_objects": Case(mm.match_objects, {**objects, "sigma": 3.0, "n_modes": 4, "align": "sign",
                                                 "search": "global", "excess": True, "element": "gaussian",
                                                 "rigid": "exact"},
                              {**object_kinds, "sigma": "positive", "n_modes": "count", "align": "name",
                               "search": "name", "excess": "flag", "element": "name", "rigid": "name"},
                              accept=frozenset({("sigma", "None")})),
        "match_coordinates": Case(mm.match_coordinates, objects, object_kinds),
        "match_cpd": Case(mm.match_cpd, {**objects, "kind": "rigid"}, {**object_kinds, "kind": "name"}),
        "make_pedobarography_sequence": Case(
            mm.make_pedobarography_sequence,
            {"rng": 0, "n_frames": 2}, {"rng": "seed", "n_frames": "count"}),
        "PedobarographySequence.pressure": Case(method(step, "pressure"), {"xy_mm": X1 + 80, "t": 3.0},
                                                {"xy_mm": "array", "t": "non_negative"}),
        "PedobarographySequence.contour": Case(method(step, "contour"), {"frame": 4, "level": 15.0, "n_nodes": 20},
                                               {"frame": "count", "level": "positive", "n_nodes": "count"},
                                               accept=frozenset({("frame", "zero")})),
        "paper_pair": Case(mm.paper_pair, {"sequence": step, "which": "isobars"},
                           {"sequence": "record", "which": "name"}),
        "frame_pair": Case(mm.frame_pair, {"sequence": step, "frame1": 3, "frame2": 6, "level": 15.0,
                                           "nodes": (20, 18)},
                           {"sequence": "object", "frame1": "count", "frame2": "count", "level": "positive",
                            "nodes": "object"},
                           names={"frame1": "frame", "frame2": "frame"},
                           accept=frozenset({("frame1", "zero"), ("frame2", "zero")})),
        "move_object": Case(mm.move_object, {"pair": pair, "angle_deg": 20.0, "shift_mm": 40.0},
                            {"pair": "object", "angle_deg": "real", "shift_mm": "real"}),
        "correct_share": Case(mm.correct_share, {"pairs": pairs, "truth": X1, "X2": X2},
                              {"pairs": "array", "truth": "array", "X2": "array"}),
    }
