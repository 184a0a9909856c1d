"""The benchmark harness: tables, timing, --json; and every benchmark script answers --help at once."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import _harness  # noqa: E402


def test_table_renders_aligned_and_refuses_a_short_row():
    table = _harness.Table("speed", ("method", "seconds", "ratio"))
    table.add("ours", 0.5, 1.0)
    table.add("peer", 12.25, float("nan"))
    lines = table.render().splitlines()
    assert lines[0] == "speed" and lines[1].split() == ["method", "seconds", "ratio"]
    assert lines[3].split() == ["ours", "0.5", "1"] and lines[4].split() == ["peer", "12.25", "n/a"]
    assert len({len(line) for line in lines[1:3]}) == 1  # header and rule have one width
    with pytest.raises(ValueError, match="needs 3 values, got 2"):
        table.add("short", 1.0)


def test_time_call_reports_best_and_median():
    calls = []
    timing, result = _harness.time_call(lambda: calls.append(1) or len(calls), repeats=3)
    assert result == 3 and len(timing.runs) == 3
    assert timing.best == min(timing.runs) and timing.best <= timing.median
    with pytest.raises(ValueError, match="repeats must be a positive int"):
        _harness.time_call(lambda: None, repeats=0)


def test_benchmark_writes_json(tmp_path, capsys):
    bench = _harness.Benchmark("demo", seed=7)
    args = bench.parse(["--json", str(tmp_path / "out.json"), "--repeats", "2"])
    assert args.seed == 7 and args.repeats == 2
    bench.table("method", "seconds").add("ours", 1.5)
    bench.tables[0].add("peer", float("nan"))
    bench.note("one note")
    bench.finish()
    record = json.loads((tmp_path / "out.json").read_text())
    assert record["tables"][0]["rows"] == [["ours", 1.5], ["peer", None]]  # strict JSON: NaN is null
    assert record["arguments"]["seed"] == 7
    assert record["notes"] == ["one note"] and record["machine"]["threads"]["OMP_NUM_THREADS"]
    assert "one note" in capsys.readouterr().out
SCRIPTS = sorted(p for p in BENCHMARKS.glob("*.py") if not p.name.startswith("_"))


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_every_script_answers_help_at_once_and_offers_json(script):
    start = time.perf_counter()
    done = subprocess.run([sys.executable, str(script), "--help"], capture_output=True, text=True, timeout=60)
    seconds = time.perf_counter() - start
    assert done.returncode == 0, done.stderr
    assert "--json" in done.stdout
    assert seconds < 10, f"{script.name} --help took {seconds:.1f} s"  # 2 s goal; loose under a loaded CI
