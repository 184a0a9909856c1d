"""Chapter 1 benchmark: robust articulated EM (Dewaele et al. 2006) vs pycpd's rigid CPD.

Prints, per condition, the median joint-angle RMSE, the share of trials with every finger joint
within 10 degrees, the noise floor (least squares with the true matches, same points) and the time
per trial, for the paper's EM settings and ours (bias-corrected targets); then the E-step against
pycpd's, the 100-frame tracking run, and rigid CPD on the same points.

Default run is short (--trials 5). The issue's protocol is 100 seeded trials per level:
    .venv/bin/python benchmarks/bench_01_em_articulated.py --trials 100
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from pycpd import RigidRegistration

from amdo_lab.common import spawn_rngs
from amdo_lab.em_articulated import (
    OUR_SETTINGS,
    PAPER_C,
    PAPER_SETTINGS,
    HandModel,
    e_step_statistics,
    e_step_statistics_kdtree,
    joint_rmse_deg,
    make_registration_problem,
    make_tracking_sequence,
    register_em,
    run_registration_trials,
    track_sequence,
)

HAND_LENGTH_MM = 190.0  # wrist to middle fingertip of HandModel, for noise as % of hand length


def conditions() -> list[tuple[str, dict]]:
    base = dict(joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0)
    rows = [("done-when: 20 deg, 2 mm, 1:1 outliers", base)]
    rows += [(f"start {e:.0f} deg", {**base, "joint_error_deg": e}) for e in (10.0, 30.0)]
    rows += [(f"noise {p:.1f} % of hand ({p * HAND_LENGTH_MM / 100:.1f} mm)", {**base, "noise_mm": p * HAND_LENGTH_MM / 100})
             for p in (0.0, 0.5, 2.0, 4.0)]
    rows += [(f"outliers {o:.1f} per inlier", {**base, "outlier_ratio": o}) for o in (0.0, 2.0)]
    rows += [("occlusion (camera side only)", {**base, "occlusion": True}),
             ("textureless (repeatability 0)", {**base, "repeatability": 0.0})]
    return rows


def registration_table(hand: HandModel, trials: int) -> None:
    print(f"{'condition':40s} {'EM settings':8s} {'median RMSE':>11s} {'success':>8s} {'floor':>6s} {'s/trial':>8s}")
    for k, (name, problem) in enumerate(conditions()):
        for label, settings in (("paper", PAPER_SETTINGS), ("ours", OUR_SETTINGS)):
            summary = run_registration_trials(hand, 1000 + k, trials, problem=problem, em_settings=settings,
                                              surface_steps=0)
            floors = summary.oracle_rmse_deg[np.isfinite(summary.oracle_rmse_deg)]
            floor = f"{np.median(floors):6.2f}" if floors.size else f"{'n/a':>6s}"  # textureless: no true matches
            print(f"{name:40s} {label:8s} {summary.median_rmse_deg:11.2f} {summary.success_rate:8.2f} "
                  f"{floor} {np.median(summary.seconds):8.2f}", flush=True)


def _per_call_ms(function, repeats: int = 10) -> float:
    start = time.perf_counter()
    for _ in range(repeats):
        function()
    return 1000 * (time.perf_counter() - start) / repeats


def e_step_table(hand: HandModel) -> None:
    """E-step on 500 texture points x 1000 data points (500 skin, 500 clutter) vs pycpd's."""
    problem = make_registration_problem(hand, 0, joint_error_deg=0.0, noise_mm=2.0, outlier_ratio=1.0)
    model, data = problem.model_points, problem.data_points
    print(f"\nE-step, {len(model)} texture x {len(data)} data points (ms per call)")
    print(f"{'sigma (mm)':>10s} {'dense':>8s} {'k-d tree':>9s} {'pycpd':>8s} {'pycpd/dense':>12s} {'pycpd/tree':>11s}")
    for sigma in (20.0, 8.0, 3.0):
        dense = _per_call_ms(lambda: e_step_statistics(model, data, sigma, np.log(PAPER_C)))
        tree = _per_call_ms(lambda: e_step_statistics_kdtree(model, data, sigma, np.log(PAPER_C)))
        peer_registration = RigidRegistration(X=data, Y=model, sigma2=sigma**2, w=0.5)
        peer = _per_call_ms(peer_registration.expectation)
        print(f"{sigma:10.0f} {dense:8.1f} {tree:9.1f} {peer:8.1f} {peer / dense:12.1f} {peer / tree:11.1f}")


def tracking_line(hand: HandModel, n_frames: int) -> None:
    """The chapter's sequence (20 fps, camera-side skin features, clutter), tracked frame to frame."""
    sequence = make_tracking_sequence(hand, 5, n_frames=n_frames, fps=20.0)
    settings = {key: value for key, value in OUR_SETTINGS.items() if key not in ("sigma_max", "sigma_min")}
    settings.update(n_levels=4, iterations_per_level=5)
    start = time.perf_counter()
    result = track_sequence(sequence.frames, hand, sequence.poses[0], sigma_max=8.0, sigma_min=3.0,
                            em_settings=settings)
    per_frame = (time.perf_counter() - start) / (n_frames - 1)
    errors = np.array([joint_rmse_deg(est, true) for est, true in zip(result.poses, sequence.poses)])
    points = [len(frame) for frame in sequence.frames]
    print(f"\ntracking {n_frames} frames ({min(points)}-{max(points)} points each): {1000 * per_frame:.0f} ms/frame "
          f"(goal < 100, aim 50); joint RMSE median {np.median(errors[1:]):.1f} deg, worst {errors.max():.1f} deg, "
          f"last {errors[-1]:.1f} deg; texture kept median {np.median(result.n_texture[1:]):.0f} (paper: about 250)")


def peer_table(hand: HandModel, trials: int) -> None:
    """Rigid CPD (pycpd 2.0, scale always estimated) vs our EM on the done-when problems."""
    rows = []
    for rng in spawn_rngs(7, trials):
        problem = make_registration_problem(hand, rng, joint_error_deg=20.0, noise_mm=2.0, outlier_ratio=1.0)
        palm_true = hand.part_transforms(problem.theta_true)[0, :3, 3]
        palm_init = hand.part_transforms(problem.theta_init)[0, :3, 3]
        row = []
        for w in (0.0, 0.5):
            start = time.perf_counter()
            _, (scale, rotation, translation) = RigidRegistration(X=problem.data_points, Y=problem.model_points, w=w).register()
            seconds = time.perf_counter() - start
            # pycpd maps row vectors as s * Y @ R + t: its R is the transpose of the column-vector rotation
            row += [np.linalg.norm(scale * palm_init @ rotation + translation - palm_true), seconds]
        start = time.perf_counter()
        em = register_em(problem.model_points, problem.data_points, hand, problem.theta_init, **OUR_SETTINGS)
        row += [np.linalg.norm(hand.part_transforms(em.theta)[0, :3, 3] - palm_true), time.perf_counter() - start]
        rows.append(row)
    med = np.median(np.array(rows), axis=0)
    print(f"\npalm centre error (mm) and time (s), median of {trials} done-when problems:")
    print(f"  rigid CPD w=0:   {med[0]:6.1f} mm {med[1]:6.2f} s")
    print(f"  rigid CPD w=0.5: {med[2]:6.1f} mm {med[3]:6.2f} s")
    print(f"  ours (EM):       {med[4]:6.1f} mm {med[5]:6.2f} s   (CPD w=0 time / ours: {med[1] / med[5]:.1f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=5, help="seeded trials per condition (issue: 100)")
    parser.add_argument("--frames", type=int, default=100, help="tracking sequence length (0: skip)")
    args = parser.parse_args()
    hand = HandModel()
    print(f"trials per condition: {args.trials}; success = every finger joint within 10 deg; "
          f"floor = fit with the true matches\n")
    registration_table(hand, args.trials)
    e_step_table(hand)
    if args.frames:
        tracking_line(hand, args.frames)
    peer_table(hand, min(args.trials, 5))


if __name__ == "__main__":
    main()
