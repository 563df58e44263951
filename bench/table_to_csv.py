#!/usr/bin/env python3
"""Turn the table that corotate_bench prints into a CSV (for bench/results/ and the docs'
benchmarks page).

    corotate bench -- --sizes 1,2,4,8 --configs default | python bench/table_to_csv.py > bench/results/beam.csv

Reads the benchmark's output on stdin: the "scenario:" and other lines ending in a colon-free
prose are skipped; the header row (it starts with "mesh" or "body") names the columns, and
every following row is split on runs of spaces, the first cells joined back into the mesh or
body name (which may hold a space, as "beam 10x2x2")."""

import csv
import sys


def rows(lines):
    header = None
    for line in lines:
        cells = line.split()
        if not cells:
            continue
        if cells[0] in ("mesh", "body"):
            header = cells
            yield header
        elif header is not None and len(cells) >= len(header):
            extra = len(cells) - len(header) + 1
            yield [" ".join(cells[:extra]), *cells[extra:]]


def main() -> int:
    writer = csv.writer(sys.stdout, lineterminator="\n")
    count = 0
    for row in rows(sys.stdin):
        writer.writerow(row)
        count += 1
    if count < 2:
        print(
            "table_to_csv: no benchmark table on stdin (a header row starting with 'mesh' or 'body')", file=sys.stderr
        )
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
