"""What every benchmark script shares: thread pinning, seeds, timing, the printed table, ``--json``.

A script uses it in this order, so ``--help`` answers before numpy or the package is imported::

    from _harness import Benchmark            # pins BLAS threads (environment, before numpy)

    bench = Benchmark(__doc__, seed=2004)
    bench.parser.add_argument("--trials", type=int, default=10)
    args = bench.parse()                       # --help exits here, at once
    import numpy as np                         # heavy imports after the arguments are parsed
    ...
    table = bench.table("method", "seconds", "ratio")
    table.add("ours", best_s, 1.0)
    bench.finish()                             # prints every table; writes --json when asked

Timings are the best and the median of ``--repeats`` runs (the best is the least disturbed by the
rest of the machine, the median says how typical it is). Ratios come from one run of the script,
so ours and the peer see the same machine state.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pin_threads(n_threads: int = 1) -> None:
    """Limit BLAS and OpenMP to ``n_threads`` through the environment (before numpy is imported)."""
    if "numpy" in sys.modules:
        raise RuntimeError("pin_threads must run before numpy is imported: import _harness first")
    for variable in _THREAD_VARIABLES:
        os.environ[variable] = str(n_threads)


# One thread unless the caller's environment already says otherwise: single-core numbers are the
# ones the chapters quote, and they do not depend on how many cores the machine has.
for _variable in _THREAD_VARIABLES:
    os.environ.setdefault(_variable, "1")


@dataclass(frozen=True)
class Timing:
    """Seconds of repeated runs of one call: ``best``, ``median`` and every run."""

    best: float
    median: float
    runs: tuple[float, ...]


def time_call(function: Callable[[], Any], repeats: int = 1) -> tuple[Timing, Any]:
    """Run ``function()`` ``repeats`` times; return its timing and the last result."""
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"repeats must be a positive int, got {repeats!r}")
    runs, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        runs.append(time.perf_counter() - start)
    return Timing(min(runs), statistics.median(runs), tuple(runs)), result


@dataclass
class Table:
    """A printed table: a title, column names and rows of numbers or words."""

    title: str
    columns: tuple[str, ...]
    rows: list[tuple[Any, ...]] = field(default_factory=list)

    def add(self, *values: Any) -> None:
        if len(values) != len(self.columns):
            raise ValueError(f"a row of {self.title!r} needs {len(self.columns)} values, got {len(values)}")
        self.rows.append(tuple(_plain(v) for v in values))

    def render(self) -> str:
        cells = [list(self.columns)] + [[_format(v) for v in row] for row in self.rows]
        widths = [max(len(row[i]) for row in cells) for i in range(len(self.columns))]
        lines = [self.title] if self.title else []
        for k, row in enumerate(cells):
            first, rest = row[0].ljust(widths[0]), [c.rjust(w) for c, w in zip(row[1:], widths[1:])]
            lines.append("  ".join([first, *rest]).rstrip())
            if k == 0:
                lines.append("  ".join("-" * w for w in widths))
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return {"title": self.title, "columns": list(self.columns), "rows": [list(r) for r in self.rows]}


class Benchmark:
    """One benchmark run: its arguments, its tables and its machine-readable record."""

    def __init__(self, description: str | None, *, seed: int | None = None, repeats: int = 1) -> None:
        self.parser = argparse.ArgumentParser(
            description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
        if seed is not None:
            self.parser.add_argument("--seed", type=int, default=seed, help=f"base seed (default {seed})")
        self.parser.add_argument("--repeats", type=int, default=repeats,
                                 help=f"timed repeats of each call; best and median are reported (default {repeats})")
        self.parser.add_argument("--json", type=Path, metavar="PATH",
                                 help="also write every table and the arguments to PATH as JSON")
        self.tables: list[Table] = []
        self.notes: list[str] = []
        self.args: argparse.Namespace | None = None
        self._start = time.perf_counter()

    def parse(self, argv: Sequence[str] | None = None) -> argparse.Namespace:
        self.args = self.parser.parse_args(argv)
        if self.args.repeats < 1:
            self.parser.error(f"--repeats must be at least 1, got {self.args.repeats}")
        return self.args

    def table(self, *columns: str, title: str = "") -> Table:
        table = Table(title, tuple(columns))
        self.tables.append(table)
        return table

    def note(self, text: str) -> None:
        """A line printed after the tables (and kept in the JSON): what a number means."""
        self.notes.append(text)

    def time(self, function: Callable[[], Any]) -> tuple[Timing, Any]:
        return time_call(function, self.args.repeats if self.args else 1)

    def finish(self) -> dict[str, Any]:
        """Print every table and note; write the JSON record when ``--json`` was given."""
        for table in self.tables:
            print(table.render(), end="\n\n")
        for text in self.notes:
            print(text)
        record = {
            "script": Path(sys.argv[0]).name,
            "arguments": {k: _plain(v) for k, v in vars(self.args or argparse.Namespace()).items()},
            "machine": {"python": platform.python_version(), "platform": platform.platform(),
                        "cpus": os.cpu_count(),
                        "threads": {v: os.environ.get(v) for v in _THREAD_VARIABLES}},
            "seconds": round(time.perf_counter() - self._start, 3),
            "tables": [t.as_dict() for t in self.tables],
            "notes": self.notes,
        }
        if self.args is not None and self.args.json is not None:
            self.args.json.parent.mkdir(parents=True, exist_ok=True)
            self.args.json.write_text(json.dumps(record, indent=1, allow_nan=False) + "\n", encoding="utf-8")
            print(f"wrote {self.args.json}")
        return record


def _plain(value: Any) -> Any:
    """numpy scalars and paths as plain Python values, NaN and inf as null: the record is strict JSON."""
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "item") and callable(value.item) and getattr(value, "shape", None) == ():
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _format(value: Any) -> str:
    if value is None:  # NaN or inf on the way in: a peer that could not run, a floor that does not exist
        return "n/a"
    if isinstance(value, float):
        return f"{value:.3g}" if abs(value) < 0.01 or abs(value) >= 1e5 else f"{value:.3f}".rstrip("0").rstrip(".")
    return str(value)
