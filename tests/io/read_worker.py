"""A child process for the file fuzz test: reads the files named on stdin, one request a
line ("<kind> <path>", kind: volume = read_mesh, surface = read_surface, embedded =
EmbeddedSurface.from_file, tetrahedralize), and answers each on stdout with one JSON line:
{"status": "ok", "cell_type", "n_cells", "n_nodes"} (n_cells: those read plus those dropped
with a warning) or {"status": "error", "type", "message"}.

Anything other than ValueError / FileNotFoundError is reported as status "escaped". A crash
or a hang shows up in the parent as a dead process or a missing answer.
"""

from __future__ import annotations

import json
import re
import sys
import warnings

import corotate as cr


def answer(kind: str, path: str) -> dict:
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            if kind == "volume":
                mesh = cr.read_mesh(path)
            elif kind == "surface":
                mesh = cr.read_surface(path)
            elif kind == "embedded":
                mesh = cr.EmbeddedSurface.from_file(cr.box(), path).mesh
            else:
                mesh = cr.tetrahedralize(path, target_cells=50)
        # The one way read_mesh may leave cells out: lower-dimensional ones, with a warning that
        # counts them (a VTK type flipped from tetra to polygon).
        dropped = [re.search(r"ignored (\d+) lower-dimensional", str(w.message)) for w in caught]
        return {
            "status": "ok",
            "cell_type": mesh.cell_type,
            "n_cells": mesh.n_cells + sum(int(d.group(1)) for d in dropped if d),
            "n_nodes": mesh.n_nodes,
        }
    except (ValueError, FileNotFoundError) as e:
        return {"status": "error", "type": type(e).__name__, "message": str(e)}
    except BaseException as e:  # SystemExit and MemoryError included on purpose
        return {"status": "escaped", "type": type(e).__name__, "message": str(e)}


def main() -> None:
    print(json.dumps({"status": "ready"}), flush=True)
    for line in sys.stdin:
        kind, path = line.rstrip("\n").split(" ", 1)
        print(json.dumps(answer(kind, path)), flush=True)


if __name__ == "__main__":
    main()
