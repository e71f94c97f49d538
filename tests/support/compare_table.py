#!/usr/bin/env python3
"""Checks that a documented Markdown table comes from a current run (issue 41).

usage: compare_table.py FRESH COMMITTED [--ignore HEADER]...

Both files hold a Markdown table (header, separator, rows). Every cell must match,
except the columns named by --ignore (run times, which vary from run to run). Exit 1
naming the first rows and columns that differ, 2 on a missing file or column."""
import sys


def table(path):
    try:
        lines = [l.strip() for l in open(path, encoding="utf-8") if l.strip().startswith("|")]
    except OSError as e:
        sys.exit(f"compare_table: {path}: {e.strerror}")
    if len(lines) < 2:
        print(f"compare_table: {path}: no Markdown table", file=sys.stderr)
        sys.exit(2)
    cells = [[c.strip() for c in l.strip("|").split("|")] for l in lines]
    return cells[0], cells[2:]


def main():
    args = sys.argv[1:]
    ignore = [args[i + 1] for i, a in enumerate(args) if a == "--ignore" and i + 1 < len(args)]
    files = [a for i, a in enumerate(args) if a != "--ignore" and (i == 0 or args[i - 1] != "--ignore")]
    if len(files) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    fresh_header, fresh = table(files[0])
    committed_header, committed = table(files[1])
    if fresh_header != committed_header:
        print(f"compare_table: {files[1]}: its columns {committed_header} are not the current run's {fresh_header}",
              file=sys.stderr)
        sys.exit(1)
    for name in ignore:
        if name not in fresh_header:
            print(f"compare_table: no column '{name}' to ignore in {files[0]}", file=sys.stderr)
            sys.exit(2)
    keep = [i for i, h in enumerate(fresh_header) if h not in ignore]
    differences = []
    if len(fresh) != len(committed):
        differences.append(f"{len(committed)} rows committed, {len(fresh)} in the current run")
    for r, (a, b) in enumerate(zip(fresh, committed)):
        for i in keep:
            x = a[i] if i < len(a) else ""
            y = b[i] if i < len(b) else ""
            if x != y:
                differences.append(f"row {r + 1} ({' '.join(a[:3])}), column '{fresh_header[i]}': "
                                   f"committed {y}, current {x}")
    if differences:
        print(f"compare_table: {files[1]} does not come from the current build "
              f"(regenerate it with scripts/accuracy):", file=sys.stderr)
        for d in differences[:10]:
            print("  " + d, file=sys.stderr)
        sys.exit(1)
    print(f"compare_table: {files[1]}: {len(fresh)} rows, {len(keep)} of {len(fresh_header)} columns "
          f"as the current run")


if __name__ == "__main__":
    main()
