"""Chapter 5: the factorial table under several OpenBLAS kernels (same seed, same code).

Each kernel runs in its own process (``OPENBLAS_CORETYPE`` is read when OpenBLAS loads), computes
``run_factorial_experiment(design, rng=SEED)`` and the counts Y are compared with the first kernel's:
the number of differing rows and the configurations (U, M, D, S) they lie in. SkylakeX is skipped
when the CPU lacks AVX-512. With ``--diagnose`` the script also prints, per training set, size and
supplement, the Fisher eigenvalue spectrum that decides how many LDA axes are well defined (the
rank of S_b in PCA space) and the condition number of S_w.

    .venv/bin/python benchmarks/dev_05_blas_kernels.py [--design paper|reduced] [--seed 2004]
        [--kernels Haswell SkylakeX Nehalem] [--diagnose] [--json PATH]
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _harness import Benchmark  # first: pins BLAS threads before numpy is imported

ROOT = Path(__file__).resolve().parents[1]

_CHILD = """
import sys, numpy as np
from amdo_lab import face_glmm as fg
design = fg.paper_design() if sys.argv[1] == "paper" else fg.reduced_design()
table = fg.run_factorial_experiment(design, rng=int(sys.argv[2]))
np.save(sys.argv[3], table.Y.to_numpy())
table[["U", "M", "D", "S"]].astype(str).to_pickle(sys.argv[3] + ".config.pkl")
"""


def has_avx512() -> bool:
    """Whether /proc/cpuinfo lists avx512f (False where it cannot be read)."""
    try:
        return "avx512f" in Path("/proc/cpuinfo").read_text()
    except OSError:
        return False


def run_kernel(kernel: str, design: str, seed: int, out: Path) -> float:
    """Run the experiment in a child process under OPENBLAS_CORETYPE=kernel; seconds taken."""
    env = dict(os.environ, OPENBLAS_CORETYPE=kernel, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               PYTHONPATH=str(ROOT))
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", _CHILD, design, str(seed), str(out)], env=env, check=True)
    return time.perf_counter() - start


def diagnose(seed: int) -> None:
    """Per (size, training set 0-1, supplement, dimension): k, rank of S_b, Fisher gap, cond(S_w)."""
    import numpy as np
    import scipy.linalg

    from amdo_lab import face_glmm as fg

    design = fg.paper_design()
    draws = fg.experiment_draws(design, rng=seed)
    n = design.n_subjects
    print("lambda_(C-1): the 63rd Fisher eigenvalue, the last the paper keeps; r: how many pass the rank")
    print("decision (> 1e-8 lambda_1); gap/lambda_1 = (lambda_r - lambda_(r+1)) / lambda_1 at r = C-1 (the")
    print("paper) and at r (ours): the inverse of the kept subspace's condition number (Davis-Kahan).")
    print("size      t supplement dim   k  odd  rank S_b   r  lambda_(C-1)/lambda_1  gap C-1   gap r  cond S_w")
    for size in ("standard", "small"):
        raw = draws.population.images if size == "standard" else fg.downsample_by_two(draws.population.images)
        faces = fg.preprocess_images(raw)
        candidates = faces.reshape(n, 4, -1)[:, 1:]
        for t in range(2):
            subjects = draws.training_sets[t]
            base = candidates[subjects].reshape(-1, *faces.shape[1:])
            for u in ("none", "reflection"):
                train = base if u == "none" else np.concatenate([base, fg.make_supplement(base, u, rng=0)])
                labels = np.tile(np.repeat(subjects, 3), len(train) // len(base))
                samples = train.reshape(len(train), -1)
                basis = fg.pca_basis(samples)
                for d in ("fixed", "e90"):
                    k = fg.PcaLda(d).fit(samples, labels, basis=basis).n_pca_
                    vectors = basis.vectors[:, :k]
                    mirrored = vectors.reshape(*faces.shape[1:], k)[:, ::-1].reshape(-1, k)
                    odd = int(np.sum(np.sum(vectors * mirrored, axis=0) < -0.5))
                    x = (samples - basis.mean) @ vectors
                    classes, inverse = np.unique(labels, return_inverse=True)
                    means = np.stack([x[inverse == c].mean(0) for c in range(classes.size)])
                    within = x - means[inverse]
                    s_w = within.T @ within
                    between = (means - x.mean(0)) * np.sqrt(len(x) / classes.size)
                    s_b = between.T @ between
                    lam = np.zeros(classes.size)  # padded with 0 where k < C - 1
                    lam[:k] = scipy.linalg.eigh(s_b, s_w, eigvals_only=True)[::-1][: classes.size] / lam_max(s_b, s_w)
                    last = classes.size - 2  # index of lambda_(C-1)
                    r = int(np.sum(lam[: last + 1] > 1e-8))
                    print(f"{size:9s} {t} {u:10s} {d:5s} {k:3d} {odd:4d} {np.linalg.matrix_rank(s_b):9d} {r:3d} "
                          f"{lam[last]:21.1e} {lam[last] - lam[last + 1]:8.1e} {lam[r - 1] - lam[r]:7.1e} "
                          f"{np.linalg.cond(s_w):9.0f}")


def lam_max(s_b, s_w) -> float:
    """The largest generalised eigenvalue of (S_b, S_w)."""
    import scipy.linalg

    n = s_b.shape[0]
    return float(scipy.linalg.eigh(s_b, s_w, eigvals_only=True, subset_by_index=[n - 1, n - 1])[0])


def main() -> None:
    bench = Benchmark(__doc__, seed=2004)
    bench.parser.add_argument("--design", choices=("paper", "reduced"), default="paper")
    bench.parser.add_argument("--kernels", nargs="+", default=["Haswell", "SkylakeX", "Nehalem"])
    bench.parser.add_argument("--diagnose", action="store_true")
    args = bench.parse()
    if args.diagnose:
        diagnose(args.seed)
        return
    kernels = [k for k in args.kernels if k != "SkylakeX" or has_avx512()]
    import numpy as np
    import pandas as pd

    report = bench.table("kernel", "seconds", f"counts differing from {kernels[0]}", "largest |difference|",
                         title=f"run_factorial_experiment({args.design} design, rng={args.seed}) per OpenBLAS kernel")
    with tempfile.TemporaryDirectory() as tmp:
        paths = {kernel: Path(tmp) / f"{kernel}.npy" for kernel in kernels}
        seconds = {kernel: run_kernel(kernel, args.design, args.seed, paths[kernel]) for kernel in kernels}
        y0 = np.load(paths[kernels[0]])
        config = pd.read_pickle(str(paths[kernels[0]]) + ".config.pkl")
        for kernel in kernels:
            y = np.load(paths[kernel])
            differ = y != y0
            report.add(kernel, round(seconds[kernel]), f"{int(differ.sum())} of {y.size}", int(np.abs(y - y0).max()))
            if differ.any():
                bench.note(f"{kernel}: differing rows by configuration (U, M, D, S):\n"
                           + config[differ].value_counts().head(10).to_string())
    bench.finish()


if __name__ == "__main__":
    main()
