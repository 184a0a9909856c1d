"""Chapter 10 benchmark: the path relinking particle filter, its peers and the paper's budgets.

Tables, one BLAS thread:
  speed    microseconds per evaluation of the weighting function (eqs. 5-7) on 160 x 160 frames with the
           eight-limb model: the reference path (every pixel) and the fast path (model pixels only, in a
           crop), best and median of --repeats over 400 poses;
  table2   Table 2 at the paper's budgets: frontal (30 frames) SIR with 4,000 evaluations a frame and
           PRPF (N 400, b 5); jump (60 frames) SIR with 1,600 and PRPF (N 200, b 5); squared angle
           errors in deg^2 (frontal: right/left elbow; jump: knee/hip) and evaluations a frame;
  peers    the frontal sequence at several budgets: SIR 500, 1,000, 4,000; pfilter 1,000; APF 8 x 60,
           8 x 250 and 8 x 500; PRPF (200, b 3) and (400, b 5); pyPESTO's scatter search (track_ess: no
           filter, a box of +-8 px, +-25 deg around the last estimate) at 500, 900 and 1,300 evaluations a
           frame: mean joint error (px), lost frames (a joint > 10 px off), evaluations a frame, seconds;
  ablation what does the work, on the frontal sequence: PRPF (200, b 3) with line paths, attribute paths
           (one limb at a time, greedy), no paths (local search from the RefSet), paths without local
           search, and the same with b 5; SIR 1,000, APF 8 x 250 and PRPF (200, b 3) with the velocity
           held at zero and estimated from the last two estimates (FilterSettings(velocity="estimate")).
Every table runs the seeds given (default 11 12 13 14 15, which the notebook and the tests do not use);
--quick runs one seed and skips the two largest SIR budgets (and, in the ablation, every run over
2,000 particles x layers); --only NAME ... runs only the named rows of every table (e.g. "ESS 1300").

Run:  .venv/bin/python benchmarks/bench_10_path_relinking_pf.py [--quick] [--seeds 11 12 ...] [--json PATH]
"""

from __future__ import annotations

from _harness import Benchmark, time_call  # first: pins BLAS threads before numpy is imported


def main() -> None:
    bench = Benchmark(__doc__, seed=11, repeats=3)
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=[11, 12, 13, 14, 15],
                              help="seeds of the tracking tables (default 11 12 13 14 15)")
    bench.parser.add_argument("--quick", action="store_true", help="one seed, no SIR at 4,000 or 1,600")
    bench.parser.add_argument("--skip-table2", action="store_true", help="skip Table 2 at the paper's budgets")
    bench.parser.add_argument("--skip-peers", action="store_true", help="skip the peers table")
    bench.parser.add_argument("--skip-ablation", action="store_true", help="skip the ablation table")
    bench.parser.add_argument("--only", nargs="+", default=None, help="run only the rows of these names")
    args = bench.parse()
    seeds = args.seeds[:1] if args.quick else args.seeds

    import numpy as np

    from amdo_lab import path_relinking_pf as pr

    seq = pr.make_upper_body_sequence(rng=args.seed, n_frames=2)
    observation = pr.ObservationModel(pr.measure(seq.frames[1], seq.background), seq.model)
    spread = np.r_[2.0, 2.0, np.full(8, np.radians(5.0))]
    poses = seq.truth[1] + spread * np.random.default_rng(0).standard_normal((400, 10))
    speed = bench.table("path", "best us / evaluation", "median us / evaluation", title="speed")
    for name, function, n in (("reference", observation.cost_reference, 100), ("fast", observation.cost, 400)):
        timing, _ = time_call(lambda: function(poses[:n]), args.repeats)
        speed.add(name, round(1e6 * timing.best / n, 1), round(1e6 * timing.median / n, 1))

    def wanted(name, kwargs, quick_limit):
        size = kwargs.get("n_particles", kwargs.get("evaluations_per_frame")) * kwargs.get("layers", 1)
        return (args.only is None or name in args.only) and not (args.quick and size > quick_limit)

    def row(table, seed, name, result, sequence, angles):
        error = pr.joint_errors_px(sequence.model, result.poses, sequence.truth)
        mse = [float(np.mean(np.degrees(result.poses[:, k] - sequence.truth[:, k]) ** 2)) for k in angles]
        table.add(seed, name, round(float(result.evaluations.mean())), round(mse[0], 1), round(mse[1], 1),
                  round(float(error.mean()), 2), round(100 * float((error.max(1) > 10).mean())),
                  round(result.seconds, 1))
        print(f"seed {seed} {name} done", flush=True)

    columns = ("seed", "run", "evaluations", "MSE a deg2", "MSE b deg2", "joint error px", "lost %", "seconds")
    if not args.skip_table2:
        table2 = bench.table(*columns, title="table2 (frontal a/b: right/left elbow; jump a/b: knee/hip)")
        for seed in seeds:
            frontal = pr.make_upper_body_sequence(rng=seed, n_frames=30)
            jump = pr.make_jump_sequence(rng=seed, n_frames=60)
            runs = [("frontal SIR 4000", "track_sir", {"n_particles": 4000}, frontal, (6, 7)),
                    ("frontal PRPF 400 b5", "track_prpf", {"n_particles": 400, "refset_size": 5}, frontal, (6, 7)),
                    ("jump SIR 1600", "track_sir", {"n_particles": 1600}, jump, (5, 4)),
                    ("jump PRPF 200 b5", "track_prpf", {"n_particles": 200, "refset_size": 5}, jump, (5, 4))]
            for name, tracker, kwargs, sequence, angles in runs:
                if not wanted(name, kwargs, 1000 if tracker == "track_sir" else 10**6):
                    continue
                row(table2, seed, name, getattr(pr, tracker)(sequence, rng=seed, **kwargs), sequence, angles)
    if not args.skip_peers:
        peers = bench.table(*columns, title="peers on the frontal sequence (a/b: right/left elbow)")
        runs = [("SIR 500", "track_sir", {"n_particles": 500}), ("SIR 1000", "track_sir", {"n_particles": 1000}),
                ("SIR 4000", "track_sir", {"n_particles": 4000}),
                ("pfilter 1000", "track_pfilter", {"n_particles": 1000}),
                ("APF 8x60", "track_apf", {"n_particles": 60, "layers": 8}),
                ("APF 8x250", "track_apf", {"n_particles": 250, "layers": 8}),
                ("APF 8x500", "track_apf", {"n_particles": 500, "layers": 8}),
                ("PRPF 200 b3", "track_prpf", {"n_particles": 200, "refset_size": 3}),
                ("PRPF 400 b5", "track_prpf", {"n_particles": 400, "refset_size": 5}),
                ("ESS 500", "track_ess", {"evaluations_per_frame": 500}),
                ("ESS 900", "track_ess", {"evaluations_per_frame": 900}),
                ("ESS 1300", "track_ess", {"evaluations_per_frame": 1300})]
        for seed in seeds:
            frontal = pr.make_upper_body_sequence(rng=seed, n_frames=30)
            for name, tracker, kwargs in runs:
                if not wanted(name, kwargs, 1000):
                    continue
                row(peers, seed, name, getattr(pr, tracker)(frontal, rng=seed, **kwargs), frontal, (6, 7))
    if not args.skip_ablation:
        ablation = bench.table(*columns, title="ablation on the frontal sequence (a/b: right/left elbow)")
        estimate = pr.FilterSettings(velocity="estimate")
        runs = [("PRPF 200 b3 line", "track_prpf", {"n_particles": 200, "refset_size": 3}),
                ("PRPF 200 b3 attribute", "track_prpf", {"n_particles": 200, "refset_size": 3, "relink": "attribute"}),
                ("PRPF 200 b3 no paths", "track_prpf", {"n_particles": 200, "refset_size": 3, "relink": "none"}),
                ("PRPF 200 b3 no local search", "track_prpf",
                 {"n_particles": 200, "refset_size": 3, "local_search": False}),
                ("PRPF 400 b5 attribute", "track_prpf", {"n_particles": 400, "refset_size": 5, "relink": "attribute"}),
                ("PRPF 400 b5 no paths", "track_prpf", {"n_particles": 400, "refset_size": 5, "relink": "none"}),
                ("PRPF 200 b3 v estimate", "track_prpf", {"n_particles": 200, "refset_size": 3, "settings": estimate}),
                ("SIR 1000 v zero", "track_sir", {"n_particles": 1000}),
                ("SIR 1000 v estimate", "track_sir", {"n_particles": 1000, "settings": estimate}),
                ("APF 8x250 v zero", "track_apf", {"n_particles": 250, "layers": 8}),
                ("APF 8x250 v estimate", "track_apf", {"n_particles": 250, "layers": 8, "settings": estimate})]
        for seed in seeds:
            frontal = pr.make_upper_body_sequence(rng=seed, n_frames=30)
            for name, tracker, kwargs in runs:
                if not wanted(name, kwargs, 2000):
                    continue
                row(ablation, seed, name, getattr(pr, tracker)(frontal, rng=seed, **kwargs), frontal, (6, 7))
    bench.note("MSE in deg^2 of the angle; lost: frames with a joint more than 10 px from the truth")
    bench.finish()


if __name__ == "__main__":
    main()
