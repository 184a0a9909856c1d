"""Chapter 9: the correct share against the frame gap, over seeds the chapter does not use.

For each seed, the foot's outline at 15 kPa in frames t and t + g (64 and 58 nodes, as Table 1), for every
start frame t with both outlines closed and gaps g = 1 ... 6, matched by modal matching (Procrustes-aligned
modes, global search), raw coordinates with the same assignment, deformable CPD then the assignment, and
nearest neighbour (each node of object 1 takes the closest node of object 2, not one-to-one). Prints each
seed's mean share per gap and method, then, per gap, the smallest margin over seeds of modal matching over
coordinates and over CPD, and of nearest neighbour over modal matching: the chapter's thresholds are set
from these with a margin.

    .venv/bin/python benchmarks/dev_09_gap_curve.py [--seeds 600 601 ... 609] [--json PATH]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

GAPS = (1, 2, 3, 4, 5, 6)


def main() -> None:
    bench = Benchmark(__doc__, seed=600)
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=list(range(600, 610)),
                              help="seeds (default 600-609, used by no chapter, test or benchmark)")
    args = bench.parse()

    import numpy as np

    from amdo_lab import modal_matching as mm

    def nearest(p):
        distances = np.linalg.norm(p.X1[:, None] - p.X2[None], axis=-1)
        return np.c_[np.arange(len(p.X1)), distances.argmin(axis=1)]

    methods = {"modal": lambda p: mm.match_objects(p.X1, p.X2).pairs,
               "coordinates": lambda p: mm.match_coordinates(p.X1, p.X2).pairs,
               "CPD deformable": lambda p: mm.match_cpd(p.X1, p.X2, kind="deformable").pairs,
               "nearest neighbour": nearest}
    table = bench.table("seed", "gap", "pairs", *methods, title="mean correct share over start frames")
    curves = {}
    for seed in args.seeds:
        sequence = mm.make_pedobarography_sequence(rng=seed)
        for gap in GAPS:
            shares = []
            for t in range(1, sequence.frames.shape[0] - gap):
                try:
                    pair = mm.frame_pair(sequence, t, t + gap)
                except ValueError:  # no closed outline at 15 kPa in one of the frames
                    continue
                shares.append([mm.correct_share(method(pair), pair.truth, pair.X2) for method in methods.values()])
            mean = np.mean(shares, axis=0)
            curves[seed, gap] = dict(zip(methods, mean))
            table.add(seed, gap, len(shares), *np.round(mean, 3))
            print("row", seed, gap, len(shares), *np.round(mean, 3), sep="\t", flush=True)
    margins = bench.table("gap", "modal - coordinates (min)", "modal - CPD (min)", "NN - modal (min)",
                          "modal (min)", title="over seeds")
    for gap in GAPS:
        rows = [curves[seed, gap] for seed in args.seeds]
        margins.add(gap, round(min(r["modal"] - r["coordinates"] for r in rows), 3),
                    round(min(r["modal"] - r["CPD deformable"] for r in rows), 3),
                    round(min(r["nearest neighbour"] - r["modal"] for r in rows), 3),
                    round(min(r["modal"] for r in rows), 3))
    bench.finish()


if __name__ == "__main__":
    main()
