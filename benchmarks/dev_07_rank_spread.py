"""Chapter 7: the noise edge and the PSNR-against-rank curve over seeds that chose nothing (Sec. 3.2).

For each seed, 80 half-size frames (101 x 103) of the still talking face (noise σ = 0.01) are learnt without
a cap; the model truncated to its first k directions is scored against the clean frames for every k. The
table gives σ estimated from the first frame (``estimate_noise``) over the true σ, the number of singular
values above the noise edge with the true and the estimated σ, the best rank, and how far below the best
PSNR the curve sits at the estimated edge and at the chapter's cap of 35. The last table is the spread of
each quantity the chapter asserts; the default seeds 301-312 are used by nothing else.

    .venv/bin/python benchmarks/dev_07_rank_spread.py [--seeds 301 ... 312] [--frames 80]
"""

from __future__ import annotations

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported


def main() -> None:
    bench = Benchmark(__doc__, seed=11)
    bench.parser.add_argument("--seeds", type=int, nargs="+", default=list(range(301, 313)),
                              help="seeds (default: 301 to 312, which chose nothing)")
    bench.parser.add_argument("--frames", type=int, default=80, help="frames per stream (default 80)")
    args = bench.parse()

    import numpy as np

    from amdo_lab import incremental_svd as isvd

    size, n = (101, 103), args.frames
    per_seed = bench.table("seed", "σ est / σ", "above edge, true σ", "above edge, σ est", "best rank",
                           "best dB", "best - at est. edge dB", "best - at cap 35 dB",
                           title=f"{n} frames of {size[0]} x {size[1]} pixels, noise 0.01")
    asserted = {name: [] for name in ("σ est / σ - 1", "above edge: est - true", "best - at est. edge dB",
                                      "best - at cap 35 dB")}
    for seed in args.seeds:
        face = isvd.make_talking_face(n, rng=seed, size=size)
        X, clean = face.frames.reshape(n, -1), face.clean.reshape(n, -1)
        model = isvd.IncrementalSVD()
        for frame in X:
            model.partial_fit(frame[None])
        sigma_hat = isvd.estimate_noise(face.frames[0])
        s = model.singular_values_
        above_true = int(np.sum(s > isvd.noise_edge(face.noise, X.shape[1], n)))
        above_hat = int(np.sum(s > isvd.noise_edge(sigma_hat, X.shape[1], n)))
        coefficients = (X - model.mean_) @ model.U_
        curve = np.array([isvd.psnr_db(model.mean_ + coefficients[:, :k] @ model.U_[:, :k].T, clean)
                          for k in range(1, s.size + 1)])
        best = int(np.argmax(curve)) + 1
        at_edge, at_cap = curve[best - 1] - curve[above_hat - 1], curve[best - 1] - curve[min(35, s.size) - 1]
        per_seed.add(seed, round(sigma_hat / face.noise, 3), above_true, above_hat, best, round(curve[best - 1], 2),
                     round(at_edge, 3), round(at_cap, 3))
        for name, value in zip(asserted, (sigma_hat / face.noise - 1, above_hat - above_true, at_edge, at_cap)):
            asserted[name].append(value)
    spread = bench.table("quantity", "min", "median", "max", title=f"spread over {len(args.seeds)} seeds")
    for name, values in asserted.items():
        spread.add(name, *[round(float(v), 3) for v in (np.min(values), np.median(values), np.max(values))])
    bench.finish()


if __name__ == "__main__":
    main()
