"""Chapter 1 benchmark: robust articulated EM (Dewaele et al. 2006) vs pycpd rigid CPD.

Default run is short (--trials 5). The issue's full protocol is 100 seeded trials per level:
    .venv/bin/python benchmarks/bench_01_em_articulated.py --trials 100
pycpd is optional (pip install -r benchmarks/requirements-01.txt); without it the peer rows are skipped.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from amdo_lab.common import spawn_rngs
from amdo_lab.em_articulated import (
    COARSE_TO_FINE_SETTINGS,
    PAPER_SETTINGS,
    HandModel,
    run_registration_trials,
    track_sequence,
    e_step_statistics,
    e_step_statistics_kdtree,
    joint_rmse_deg,
    make_registration_problem,
    make_tracking_sequence,
    register_em,
)


def run_level(hand: HandModel, trials: int, seed: int, settings: dict, **problem_kwargs) -> dict:
    summary = run_registration_trials(hand, seed, trials, problem=problem_kwargs, em_settings=settings)
    return {"median_rmse_deg": summary.median_rmse_deg, "success": summary.success_rate,
            "seconds": float(np.median(summary.seconds))}


def peer_rigid_cpd(hand: HandModel, trials: int, seed: int) -> list[str]:
    try:
        from pycpd import RigidRegistration  # lazy: peer for the benchmark only
    except ImportError:
        return ["pycpd not installed: pip install -r benchmarks/requirements-01.txt"]
    rows = []
    for rng in spawn_rngs(seed, trials):
        problem = make_registration_problem(hand, rng, joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0)
        start = time.perf_counter()
        reg = RigidRegistration(X=problem.data_points, Y=problem.model_points, w=0.5)
        _, (scale, rotation, translation) = reg.register()
        cpd_seconds = time.perf_counter() - start
        # pycpd maps Y -> s Y R + t (row vectors), so its R is the transpose of the column-vector rotation
        start = time.perf_counter()
        em = register_em(problem.model_points, problem.data_points, hand, problem.theta_init, **COARSE_TO_FINE_SETTINGS)
        em_seconds = time.perf_counter() - start
        palm_true = hand.part_transforms(problem.theta_true)[0, :3, 3]
        palm_init = hand.part_transforms(problem.theta_init)[0, :3, 3]
        cpd_palm = scale * palm_init @ rotation + translation
        em_palm = hand.part_transforms(em.theta)[0, :3, 3]
        rows.append((np.linalg.norm(cpd_palm - palm_true), np.linalg.norm(em_palm - palm_true), cpd_seconds, em_seconds))
    r = np.median(np.array(rows), axis=0)
    return [f"palm position error (mm): pycpd rigid {r[0]:.1f}, ours {r[1]:.1f}; "
            f"time (s): pycpd {r[2]:.2f}, ours {r[3]:.2f}, ratio {r[2] / r[3]:.1f}"]


def _per_call_ms(function, repeats: int = 10) -> float:
    start = time.perf_counter()
    for _ in range(repeats):
        function()
    return 1000 * (time.perf_counter() - start) / repeats


def e_step_timing(hand: HandModel) -> list[str]:
    """E-step on 500 texture points x 1000 data points (500 on the hand, 500 clutter)."""
    rng = spawn_rngs(0, 1)[0]
    theta = hand.rest_pose()
    model = hand.sample_surface(theta, 500, rng)
    data = np.concatenate([hand.sample_surface(theta, 500, rng), rng.uniform(-100, 150, size=(500, 3))])
    lines = ["E-step, 500 texture x 1000 data points (ms per call):",
             f"{'sigma (mm)':>10s} {'dense':>8s} {'k-d tree':>9s} {'pycpd':>8s} {'pycpd/tree':>11s}"]
    try:
        from pycpd import RigidRegistration  # lazy: peer for the benchmark only
    except ImportError:
        RigidRegistration = None
    for sigma in (20.0, 8.0, 4.0):
        dense = _per_call_ms(lambda: e_step_statistics(model, data, sigma, np.log(0.1)))
        tree = _per_call_ms(lambda: e_step_statistics_kdtree(model, data, sigma, np.log(0.1)))
        peer = float("nan")
        if RigidRegistration is not None:
            reg = RigidRegistration(X=data, Y=model, sigma2=sigma**2, w=0.5)
            peer = _per_call_ms(reg.expectation)
        lines.append(f"{sigma:10.0f} {dense:8.1f} {tree:9.1f} {peer:8.1f} {peer / tree:11.1f}")
    return lines


def tracking_run(hand: HandModel, n_frames: int) -> list[str]:
    """The issue's sequence (20 fps, camera-side points, clutter), tracked frame to frame."""
    sequence = make_tracking_sequence(hand, 5, n_frames=n_frames, fps=20.0, n_surface=1000)
    start = time.perf_counter()
    result = track_sequence(sequence.frames, hand, sequence.poses[0], sigma_max=8.0, sigma_min=3.0,
                            em_settings={"outlier_c": 0.1, "e_step": "kdtree", "iterations_per_level": 3})
    per_frame = (time.perf_counter() - start) / (n_frames - 1)
    errors = np.array([joint_rmse_deg(est, true) for est, true in zip(result.poses, sequence.poses)])
    return [f"tracking {n_frames} frames: {1000 * per_frame:.0f} ms/frame (goal < 100), joint RMSE median "
            f"{np.median(errors[1:]):.1f} deg, max {errors.max():.1f} deg, frames over 10 deg: {int(np.sum(errors > 10))}, "
            f"texture kept median {np.median(result.n_texture[1:]):.0f} (paper: about 250)"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--trials", type=int, default=5, help="seeded trials per level (issue: 100)")
    parser.add_argument("--frames", type=int, default=100, help="tracking sequence length (0: skip)")
    args = parser.parse_args()
    hand = HandModel()
    print(f"trials per level: {args.trials}")
    print(f"{'condition':38s} {'settings':15s} {'median joint RMSE (deg)':>24s} {'success':>8s} {'s/trial':>8s}")
    levels = [("done-when: 20 deg, 2 mm, 1:1 outliers", dict(joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0))]
    levels += [(f"init {e:.0f} deg, 2 mm, 1:1", dict(joint_error_deg=e, noise_mm=2.0, outlier_ratio=1.0)) for e in (10.0, 30.0)]
    levels += [(f"noise {n:.0f} mm, 20 deg, 1:1", dict(joint_error_deg=20.0, noise_mm=n, outlier_ratio=1.0)) for n in (0.0, 4.0, 8.0)]
    levels += [(f"outliers {o:.0f}:1, 20 deg, 2 mm", dict(joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=o)) for o in (0.0, 2.0)]
    levels += [("occlusion (camera side), 20 deg", dict(joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0, occlusion=True))]
    for k, (name, kwargs) in enumerate(levels):
        for label, settings in (("paper", PAPER_SETTINGS), ("coarse-to-fine", COARSE_TO_FINE_SETTINGS)):
            r = run_level(hand, args.trials, 1000 + k, settings, **kwargs)
            print(f"{name:38s} {label:15s} {r['median_rmse_deg']:24.2f} {r['success']:8.2f} {r['seconds']:8.2f}")
    for line in e_step_timing(hand):
        print(line)
    if args.frames:
        for line in tracking_run(hand, args.frames):
            print(line)
    for line in peer_rigid_cpd(hand, min(args.trials, 5), 7):
        print(line)


if __name__ == "__main__":
    main()
