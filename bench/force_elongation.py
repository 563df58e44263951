#!/usr/bin/env python3
"""The paper's force-feedback example (section 2.2.3, Fig. 8) and a bending case: reaction
force at a prescribed beam end, linear / co-rotational / co-rotational with averaged-stiffness
feedback / full nonlinear StVK, written as CSVs and one PNG.

    python bench/force_elongation.py --out force-elongation
"""

import argparse
from pathlib import Path

import numpy as np

from corotate.force_elongation import CURVES, force_curves, plot, write_csv


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="force-elongation", help="output folder (default: force-elongation)")
    parser.add_argument("--cells", type=int, nargs=3, default=(20, 4, 4), help="cubes per direction (default 20 4 4)")
    parser.add_argument("--levels", type=int, default=10, help="displacement levels (default 10)")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for case in ("pull", "bend"):
        result = force_curves(case, tuple(args.cells), args.levels)
        results[case] = result
        write_csv(result, out / f"{case}.csv")
        print(f"{case}: {result['tets']} tets, {result['tool_elements']} around the tool; at the last level:")
        reference = result["stvk"]
        for c in CURVES:
            gap = np.max(np.abs(result[c] - reference)) / np.max(np.abs(reference))
            print(f"  {c:13s} {result[c][-1] / 1e6:9.4f} MN   max distance from StVK {100 * gap:6.1f} % of its peak")
    png = plot(results, out / "force_elongation.png")
    print(f"wrote {out}/pull.csv, {out}/bend.csv" + (f" and {png}" if png else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
