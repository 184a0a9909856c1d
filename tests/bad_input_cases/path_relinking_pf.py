"""Bad-input table of ``amdo_lab.path_relinking_pf``: a valid call and the kind of each argument.

The valid inputs are tiny: a three-frame 120 x 120 sequence, a handful of particles.
"""

from __future__ import annotations

import numpy as np

from bad_input_cases._core import Case

#: (callable, argument, spoiled label) calls known to fail the test, with the reason; each must
#: still fail (remove it once fixed).
KNOWN_FAILURES: dict[tuple[str, str, str], str] = {}

#: Public names not called with user input, with the reason.
EXEMPT = {
    "BodySequence": "a result record, built by make_upper_body_sequence and make_jump_sequence (check_sequence "
                    "checks one handed back)",
    "Measurement": "a result record, built by measure from checked input",
    "TrackResult": "a result record, built by the track_* functions from checked input",
    "Limb": "a row of Table 1, checked when a BodyModel is built from it (the BodyModel case)",
    "BodyModel.jumper": "a named model of Table 1, takes no argument",
    "BodyModel.upper_body": "a named model of Table 1, takes no argument",
    "Limb.outline": "takes no argument",
}

#: Every setting of a particle filter (FilterSettings' defaults).
_SETTINGS = {"alpha": 0.01, "diffusion_px": 2.0, "diffusion_deg": 5.0, "velocity_px": 1.0, "velocity_deg": 3.0,
             "init_px": 2.0, "init_deg": 5.0, "step_px": 2.0, "step_deg": 4.0}

#: A pose may be one (P,) or a stack (N, P).
_ONE_OR_MANY = frozenset({("poses", "one more axis")})


def cases() -> dict[str, Case]:
    """The public callables of ``amdo_lab.path_relinking_pf``, by name."""
    from amdo_lab import path_relinking_pf as pr

    seq = pr.make_upper_body_sequence(rng=0, n_frames=3, size=(120, 120))
    model = seq.model
    observation = pr.ObservationModel(pr.measure(seq.frames[0], seq.background), model)
    pose = seq.truth[0]
    poses = seq.truth[:2]
    moves = np.r_[1.0, 1.0, np.full(8, 0.03)]
    tracking = {"sequence": seq, "rng": 0, "n_particles": 6, "settings": pr.FilterSettings()}
    tracking_kinds = {"sequence": "object", "rng": "seed", "n_particles": "count", "settings": "object"}

    def method(owner, name):
        return lambda **kwargs: getattr(owner, name)(**kwargs)

    def body(limbs):
        return pr.BodyModel(limbs)

    def observation_of(measurement, model, alpha):
        return pr.ObservationModel(measurement, model, alpha=alpha)

    return {
        "BodyModel": Case(body, {"limbs": model.limbs}, {"limbs": "object"}),
        "BodyModel.forward": Case(method(model, "forward"), {"poses": poses}, {"poses": "array"},
                                  accept=_ONE_OR_MANY),
        "BodyModel.joint_positions": Case(method(model, "joint_positions"), {"poses": poses}, {"poses": "array"},
                                          accept=_ONE_OR_MANY),
        "BodyModel.check_poses": Case(method(model, "check_poses"), {"poses": poses, "name": "poses"},
                                      {"poses": "array"}, accept=_ONE_OR_MANY),
        "BodyModel.render_labels": Case(method(model, "render_labels"), {"pose": pose, "shape": (120, 120)},
                                        {"pose": "array", "shape": "object"}),
        "FilterSettings": Case(pr.FilterSettings, {**_SETTINGS, "velocity": "estimate"},
                               {"alpha": "positive", "velocity": "name",
                                **{name: "non_negative" for name in _SETTINGS if name.endswith(("_px", "_deg"))
                                   and not name.startswith("step_")},
                                "step_px": "positive", "step_deg": "positive"}),
        "ObservationModel": Case(observation_of, {"measurement": observation.measurement, "model": model,
                                                  "alpha": 0.01},
                                 {"measurement": "record", "model": "object", "alpha": "positive"}),
        "ObservationModel.cost": Case(method(observation, "cost"), {"poses": poses}, {"poses": "array"},
                                      accept=_ONE_OR_MANY),
        "ObservationModel.cost_reference": Case(method(observation, "cost_reference"), {"poses": poses},
                                                {"poses": "array"}, accept=_ONE_OR_MANY),
        "ObservationModel.log_weights": Case(method(observation, "log_weights"), {"costs": np.array([10.0, 20.0])},
                                             {"costs": "array"},
                                             accept=frozenset({("costs", "a wrong trailing axis")})),  # any N
        "attribute_path": Case(pr.attribute_path, {"observation": observation, "start": pose, "guide": poses[1]},
                               {"observation": "object", "start": "array", "guide": "array"}),
        "check_sequence": Case(pr.check_sequence, {"sequence": seq}, {"sequence": "record"}),
        "edge_map": Case(pr.edge_map, {"labels": np.eye(4, dtype=int)}, {"labels": "array"},
                         accept=frozenset({("labels", "a wrong trailing axis")})),  # any image
        "joint_errors_px": Case(pr.joint_errors_px, {"model": model, "poses": poses, "truth": poses + 1.0},
                                {"model": "object", "poses": "array", "truth": "array"}),
        "line_path": Case(pr.line_path, {"start": np.zeros(3), "end": np.full(3, 4.0), "steps": np.ones(3)},
                          {"start": "array", "end": "array", "steps": "array"}),
        "relink_pair": Case(pr.relink_pair, {"observation": observation, "start": pose, "end": poses[1],
                                             "steps": moves, "start_cost": 100.0},
                            {"observation": "object", "start": "array", "end": "array", "steps": "array",
                             "start_cost": "non_negative"}),
        "relink_stage": Case(pr.relink_stage, {"observation": observation, "refset": poses,
                                               "costs": np.array([100.0, 200.0]), "settings": pr.FilterSettings(),
                                               "relink": "line", "local_search": True, "max_rounds": 1},
                             {"observation": "object", "refset": "array", "costs": "array", "settings": "object",
                              "relink": "name", "local_search": "flag", "max_rounds": "count"}),
        "local_search": Case(pr.local_search, {"observation": observation, "starts": poses, "moves": moves,
                                               "sweeps": 1},
                             {"observation": "object", "starts": "array", "moves": "array", "sweeps": "count"}),
        "make_upper_body_sequence": Case(pr.make_upper_body_sequence,
                                         {"rng": 0, "n_frames": 2, "size": (120, 120), "noise": 8.0, "speed": 1.0,
                                          "cross": True},
                                         {"rng": "seed", "n_frames": "count", "size": "object",
                                          "noise": "non_negative", "speed": "positive", "cross": "flag"}),
        "make_jump_sequence": Case(pr.make_jump_sequence, {"rng": 0, "n_frames": 2, "size": (150, 150),
                                                           "noise": 8.0},
                                   {"rng": "seed", "n_frames": "count", "size": "object", "noise": "non_negative"}),
        "measure": Case(pr.measure, {"frame": seq.frames[0], "background": seq.background, "threshold": 25.0,
                                     "canny": (40.0, 120.0), "sigma": 1.5},
                        {"frame": "image", "background": "image", "threshold": "positive", "canny": "array",
                         "sigma": "positive"}),
        "track_sir": Case(pr.track_sir, tracking, tracking_kinds),
        "track_pfilter": Case(pr.track_pfilter, tracking, tracking_kinds),
        "track_ess": Case(pr.track_ess, {"sequence": seq, "rng": 0, "evaluations_per_frame": 100},
                          {"sequence": "object", "rng": "seed", "evaluations_per_frame": "count"}),
        "track_apf": Case(pr.track_apf, {**tracking, "layers": 2, "survival": 0.5},
                          {**tracking_kinds, "layers": "count", "survival": "probability"}),
        "track_prpf": Case(pr.track_prpf, {**tracking, "refset_size": 2, "relink": "attribute", "local_search": True,
                                           "max_rounds": 1},
                           {**tracking_kinds, "refset_size": "count", "relink": "name", "local_search": "flag",
                            "max_rounds": "count"}),
    }
