#!/usr/bin/env python3
"""Medians of marionette_bench's JSON output as CSV: one summary table and the
two scaling series (joints, characters) that scripts/plot_scaling.gp plots."""
import json
import sys
from pathlib import Path

data = json.loads(Path(sys.argv[1]).read_text())
out = Path(sys.argv[2])
medians = [b for b in data["benchmarks"] if b.get("aggregate_name") == "median"]

rows = ["benchmark,us_per_char"]
joints = ["joints,us_per_char"]
chars = ["characters,us_per_char"]
for b in medians:
    name = b["run_name"]
    us = b["us_per_char"]
    rows.append(f"{name},{us:.4f}")
    if name.startswith("Scaling/Joints/"):
        joints.append(f"{name.rsplit('/', 1)[1]},{us:.4f}")
    elif name.startswith("Scaling/Characters/"):
        chars.append(f"{name.rsplit('/', 1)[1]},{us:.4f}")

(out / "bench_medians.csv").write_text("\n".join(rows) + "\n")
(out / "scaling_joints.csv").write_text("\n".join(joints) + "\n")
(out / "scaling_characters.csv").write_text("\n".join(chars) + "\n")
ctx = data.get("context", {})
print(f"{ctx.get('host_name', '?')}: {ctx.get('num_cpus', '?')} cpus @ {ctx.get('mhz_per_cpu', '?')} MHz, "
      f"{len(medians)} medians")
for r in rows[1:]:
    print("  " + r)
