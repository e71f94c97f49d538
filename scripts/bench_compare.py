#!/usr/bin/env python3
"""Compares two bench_medians.csv files (scripts/bench_to_csv.py): did a rerun reproduce them?

A benchmark agrees when its new median is within the stated spread of the old one: the ratio
new/old differs from 1 by no more than the larger of the two rows' spread_pct (the fastest to the
slowest repetition, in percent of the median). Prints every benchmark that does not, the ratio
and both spreads, worst first, then a summary; benchmarks present in one file only are listed.

Runs on different days also differ by a factor common to every benchmark (this VM's speed that
day: third-party code such as OpenCV moves with ours). So each benchmark is judged a second way,
relative to the others: its ratio divided by the median ratio of all of them. A change of the
code shows in both; a change of the machine only in the first.

Usage: bench_compare.py OLD.csv NEW.csv    (exit 0: this reports, the machine is noisy)
"""
import csv
import statistics
import sys


def load(path):
    with open(path, newline="") as f:
        return {r["benchmark"]: r for r in csv.DictReader(f) if r.get("time_median")}


old, new = load(sys.argv[1]), load(sys.argv[2])
common = sorted(set(old) & set(new))


def ratios(scale):
    """(excess over the spread in points, name, ratio / scale, spread old, spread new) per benchmark."""
    rows = []
    for name in common:
        o, n = old[name], new[name]
        if o["time_unit"] != n["time_unit"]:
            print(f"{name}: units {o['time_unit']} -> {n['time_unit']}; not compared")
            continue
        ratio = float(n["time_median"]) / float(o["time_median"]) / scale
        so, sn = float(o["spread_pct"] or 0), float(n["spread_pct"] or 0)
        rows.append((abs(ratio - 1) * 100 - max(so, sn), name, ratio, so, sn))
    return rows


raw = ratios(1.0)
machine = statistics.median(r[2] for r in raw)
for label, rows in (("as measured", raw), (f"relative (divided by the median ratio {machine:.3f})", ratios(machine))):
    outside = sorted((r for r in rows if r[0] > 0), reverse=True)
    print(f"{label}: {len(rows) - len(outside)} of {len(rows)} within the stated spread, "
          f"ratios {min(r[2] for r in rows):.3f}-{max(r[2] for r in rows):.3f}")
    for excess, name, ratio, so, sn in outside:
        print(f"  {name}: {ratio:.3f}x (spreads {so:.1f} % / {sn:.1f} %)")
for name in sorted(set(old) - set(new)):
    print(f"only in {sys.argv[1]}: {name}")
for name in sorted(set(new) - set(old)):
    print(f"only in {sys.argv[2]}: {name}")
