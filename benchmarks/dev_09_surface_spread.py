"""Chapter 9: Table 3's surface claims over seeds the chapter does not use, and the mode count chosen apart.

Two disjoint groups of seeds: on the *selection* seeds (default 620-624) the global correct share is swept
over the number of modes (exact rigid modes, Procrustes alignment), which is how a mode count is chosen; on
the *check* seeds (default 610-619) every column of the chapter's surface table is measured at the chosen
count (12), and the spread of each asserted quantity is printed: the chapter's thresholds are set from it.

    .venv/bin/python benchmarks/dev_09_surface_spread.py [--check 610 ... 619] [--select 620 ... 624]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

MODE_COUNTS = (6, 9, 12, 15, 24)


def main() -> None:
    bench = Benchmark(__doc__, seed=610)
    bench.parser.add_argument("--check", type=int, nargs="+", default=list(range(610, 620)))
    bench.parser.add_argument("--select", type=int, nargs="+", default=list(range(620, 625)))
    args = bench.parse()

    import numpy as np

    from amdo_lab import modal_matching as mm

    def pair(seed):
        return mm.paper_pair(mm.make_pedobarography_sequence(rng=seed), "surfaces")

    def share(result, p):
        return mm.correct_share(result.pairs, p.truth, p.X2)

    sweep = bench.table("seed", *map(str, MODE_COUNTS), title="selection seeds: global share by mode count")
    for seed in args.select:
        p = pair(seed)
        row = [round(share(mm.match_objects(p.X1, p.X2, n_modes=n, rigid="exact"), p), 3) for n in MODE_COUNTS]
        sweep.add(seed, *row)
        print("sweep", seed, *row, sep="\t", flush=True)
    columns = ("global", "local correct", "local kept", "24 own modes", "sign global", "3-D coordinates",
               "x, y only", "ADCom distance / h", "ADCom right")
    table = bench.table("seed", *columns, title="check seeds, 12 modes, exact rigid modes")
    for seed in args.check:
        p = pair(seed)
        best, local = (mm.match_objects(p.X1, p.X2, search=s, n_modes=12, rigid="exact") for s in ("global", "local"))
        to_truth = np.linalg.norm(p.X2[best.excess_pairs[:, 1]] - p.truth[best.excess_pairs[:, 0]], axis=1)
        plate = mm.match_coordinates(p.X1[:, :2], p.X2[:, :2])
        row = [share(best, p), share(local, p), len(local.pairs) / len(p.X2),
               share(mm.match_objects(p.X1, p.X2, n_modes=24), p),
               share(mm.match_objects(p.X1, p.X2, align="sign", n_modes=12, rigid="exact"), p),
               share(mm.match_coordinates(p.X1, p.X2), p),
               mm.correct_share(plate.pairs, p.truth[:, :2], p.X2[:, :2]),
               float(to_truth.mean() / mm.mean_spacing(p.X2)), mm.correct_share(best.excess_pairs, p.truth, p.X2)]
        table.add(seed, *np.round(row, 3))
        print("check", seed, *np.round(row, 3), sep="\t", flush=True)
    bench.finish()


if __name__ == "__main__":
    main()
