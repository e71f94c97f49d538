#!/usr/bin/env python3
"""marionette_bench's JSON output (every repetition, --benchmark_out) as CSV files.

  bench_medians.csv   one row per benchmark:
      benchmark          Google Benchmark's name
      repetitions        how many repetitions the row is computed from (errored ones excluded)
      time_unit          unit of the three time columns (the benchmark's own: ns, us or ms)
      time_median        median over the repetitions of the wall time per iteration
      time_min, time_max the fastest and slowest repetition (the spread)
      spread_pct         (time_max - time_min) / time_median, in percent
      us_per_char_median, us_per_char_min, us_per_char_max
                         the counter us_per_char (microseconds per character per frame) the same
                         way; empty for benchmarks without that counter (Speech, Stage, BML, ...)
      error              the benchmark's SkipWithError message, if any repetition reported one
                         (when all did, the other columns are empty)
  bench_counters.csv  every counter of every benchmark: benchmark,counter,repetitions,median,min,max
  bench_current.md    the same medians as a Markdown table (docs/benchmarks.md links it: the
                      current figure of every benchmark, with its spread and the run's date)
  scaling_joints.csv, scaling_characters.csv
                      the two scaling series scripts/plot_scaling.gp plots (us_per_char: median,
                      min, max)

Usage: bench_to_csv.py BENCH.json OUT_DIR
"""
import json
import statistics
import sys
from pathlib import Path

data = json.loads(Path(sys.argv[1]).read_text())
out = Path(sys.argv[2])

# Keys of a run that are not counters (Google Benchmark 1.7's JSON reporter).
NOT_COUNTERS = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
    "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit",
    "aggregate_name", "aggregate_unit", "error_occurred", "error_message", "label",
    "big_o", "rms",
}


def fmt(x):
    return f"{x:.6g}"


def quoted(message):
    return '"' + message.replace('"', "'") + '"'


# The repetitions themselves (run_type "iteration"), grouped by benchmark in the program's order;
# Google's own aggregates are not used, so one repetition gives a row too.
runs = {}
errors = {}
for b in data["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue
    name = b.get("run_name", b["name"])
    runs.setdefault(name, [])
    if b.get("error_occurred"):
        errors[name] = b.get("error_message", "error")
    else:
        runs[name].append(b)

rows = ["benchmark,repetitions,time_unit,time_median,time_min,time_max,spread_pct,"
        "us_per_char_median,us_per_char_min,us_per_char_max,error"]
counters = ["benchmark,counter,repetitions,median,min,max"]
joints = ["joints,us_per_char_median,us_per_char_min,us_per_char_max"]
chars = ["characters,us_per_char_median,us_per_char_min,us_per_char_max"]
current = []  # (name, repetitions, unit, median, spread, us_per_char median or None, error) for bench_current.md
for name, reps in runs.items():
    if not reps:
        rows.append(f"{name},0,,,,,,,,,{quoted(errors.get(name, 'no repetition'))}")
        current.append((name, 0, "", None, None, None, errors.get(name, "no repetition")))
        continue
    times = [r["real_time"] for r in reps]
    median = statistics.median(times)
    spread = 100.0 * (max(times) - min(times)) / median if median else 0.0
    per_char = ["", "", ""]
    per_char_median = None
    names = [k for k in reps[0] if k not in NOT_COUNTERS and isinstance(reps[0][k], (int, float))]
    for counter in names:
        values = [r[counter] for r in reps if counter in r]
        stats = [statistics.median(values), min(values), max(values)]
        counters.append(f"{name},{counter},{len(values)}," + ",".join(fmt(v) for v in stats))
        if counter == "us_per_char":
            per_char = [fmt(v) for v in stats]
            per_char_median = stats[0]
    message = quoted(errors[name]) if name in errors else ""
    rows.append(f"{name},{len(reps)},{reps[0]['time_unit']},{fmt(median)},{fmt(min(times))},"
                f"{fmt(max(times))},{spread:.1f},{','.join(per_char)},{message}")
    current.append((name, len(reps), reps[0]["time_unit"], median, spread, per_char_median, None))
    if per_char[0] and name.startswith("Scaling/Joints/"):
        joints.append(f"{name.rsplit('/', 1)[1]},{','.join(per_char)}")
    elif per_char[0] and name.startswith("Scaling/Characters/"):
        chars.append(f"{name.rsplit('/', 1)[1]},{','.join(per_char)}")

(out / "bench_medians.csv").write_text("\n".join(rows) + "\n")

# The Markdown view: one row per benchmark, the program's order.
ctx = data.get("context", {})
md = ["# Every benchmark, current figures", "",
      f"Written by `scripts/benchmarks` (scripts/bench_to_csv.py) on {ctx.get('date', '?')}: "
      f"{ctx.get('num_cpus', '?')} CPUs, pinned to one. Median over the repetitions, and the spread "
      "(fastest to slowest repetition, in percent of the median); between runs of different days "
      "the figures move by more (docs/benchmarks.md, \"Does a rerun reproduce\").", "",
      "| benchmark | repetitions | median | spread | µs per character |", "|---|---|---|---|---|"]
unit_name = {"ns": "ns", "us": "µs", "ms": "ms", "s": "s"}
for name, reps, unit, median, spread, per_char, error in current:
    if median is None:
        md.append(f"| `{name}` | 0 | error: {error} | | |")
        continue
    md.append(f"| `{name}` | {reps} | {median:.4g} {unit_name.get(unit, unit)} | {spread:.1f} % | "
              + (f"{per_char:.3g} |" if per_char is not None else "|"))
(out / "bench_current.md").write_text("\n".join(md) + "\n")
(out / "bench_counters.csv").write_text("\n".join(counters) + "\n")
(out / "scaling_joints.csv").write_text("\n".join(joints) + "\n")
(out / "scaling_characters.csv").write_text("\n".join(chars) + "\n")
print(f"{ctx.get('host_name', '?')}: {ctx.get('num_cpus', '?')} cpus @ {ctx.get('mhz_per_cpu', '?')} MHz, "
      f"{len(runs)} benchmarks, {len(errors)} with errors")
for r in rows[1:]:
    print("  " + r)
if errors:
    print(f"{len(errors)} benchmark(s) reported an error: " + ", ".join(sorted(errors)), file=sys.stderr)
    sys.exit(1)
