"""Why capped, warm-started PCG runs away (docs/notes/performance.md, the warm-start run-away).

Two computations:

1. The modal model. For one mode of M + dt^2 K (s = dt^2 omega^2), the linearised backward-Euler
   step wants D* = dt dv* = -s (x + dt v) / (1 + s). A capped solve removes the fraction 1 - q of
   its initial error in that mode. Cold-started, the initial guess is 0, so D = (1 - q) D*;
   warm-started it is the previous step's D, so D = (1 - q) D* + q D_prev: the un-removed part
   of the acceleration is carried over. The script prints the spectral radius of the step's
   recurrence on (x, dt v, D_prev): for every s it is 1 exactly at q = 1/2 when warm-started,
   above 1 (growth) beyond, and below 1 for every q when cold-started.

2. What 20 Jacobi-PCG iterations remove on the benchmark beams: the condition number kappa of
   the Jacobi-scaled rest system M + dt^2 K (fixed DOFs removed; extreme eigenvalues by
   Lanczos) and the Chebyshev bound q <= 1 / T_20((kappa + 1) / (kappa - 1)) on the part of the
   error left in the worst mode.

    python -m studies.warm_start_runaway --out warm-start [--sizes 2,4,8]
writes spectral_radius.csv, jacobi_condition.csv and spectral_radius.png.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import corotate as cr

from ._common import output_folder, parser, pyplot, save_figure, write_csv

MODES = (1e-3, 1e-1, 1.0, 1e2, 1e4)  # s = dt^2 omega^2


def spectral_radius(s: float, q: float, warm: bool) -> float:
    """Largest |eigenvalue| of one step's map of (x, dt v, D_prev) for mode s and leftover q."""
    c = -s / (1 + s)
    d = np.array([(1 - q) * c, (1 - q) * c, q if warm else 0.0])
    v = np.array([0.0, 1.0, 0.0]) + d
    x = np.array([1.0, 0.0, 0.0]) + v
    return float(max(abs(np.linalg.eigvals(np.vstack([x, v, d])))))


def jacobi_condition_number(size: int, dt: float = 0.01) -> tuple[int, float]:
    """(tets, kappa) of D^-1/2 (M + dt^2 K) D^-1/2 at rest for the benchmark beam of this size."""
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(10 * size, 2 * size, 2 * size), element="tet4")
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0))
    a = (body.mass_matrix() + dt * dt * body.tangent_matrix()).tocsr()
    free = np.setdiff1d(np.arange(a.shape[0]), (3 * mesh.nodes_on_plane("x", 0.0)[:, None] + np.arange(3)).ravel())
    a = a[free][:, free]
    scale = sp.diags(1.0 / np.sqrt(a.diagonal()))
    a = (scale @ a @ scale).tocsc()
    largest = spla.eigsh(a, k=1, which="LA", return_eigenvectors=False)[0]
    smallest = spla.eigsh(a, k=1, sigma=0.0, which="LM", return_eigenvectors=False)[0]
    return len(mesh.cells), float(largest / smallest)


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "warm-start")
    p.add_argument("--sizes", default="2,4,8", help="beam refinement factors (4 -> 15,360 tets, 8 -> 122,880)")
    p.add_argument("--iterations", type=int, default=20, help="the PCG cap")
    args = p.parse_args(argv)
    out = output_folder(args.out)

    print("spectral radius of one step (> 1: the mode grows)")
    qs = (0.1, 0.3, 0.5, 0.6, 0.7, 0.9)
    print("s = dt^2 w^2 " + " ".join(f"  q={q}: cold  warm" for q in qs))
    for s in MODES:
        cells = " ".join(f"{spectral_radius(s, q, False):11.4f} {spectral_radius(s, q, True):5.3f}" for q in qs)
        print(f"{s:12g} {cells}")
    grid = np.linspace(0.0, 0.95, 39)
    rows = [[s, float(q), spectral_radius(s, q, False), spectral_radius(s, q, True)] for s in MODES for q in grid]
    write_csv(out / "spectral_radius.csv", ["s", "q", "cold", "warm"], rows)

    print(f"\nJacobi-scaled rest system and the error left after {args.iterations} CG iterations")
    print("tets  kappa  Chebyshev bound on q")
    rows = []
    for size in (int(s) for s in args.sizes.split(",")):
        tets, kappa = jacobi_condition_number(size)
        bound = 1.0 / np.cosh(args.iterations * np.arccosh((kappa + 1) / (kappa - 1)))
        rows.append([tets, kappa, float(bound)])
        print(f"{tets}  {kappa:.0f}  {bound:.3f}")
    write_csv(out / "jacobi_condition.csv", ["tets", "kappa", "chebyshev_bound_on_q"], rows)

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, s in enumerate(MODES):
        ax.plot(grid, [spectral_radius(s, q, True) for q in grid], "-", color=f"C{k}", label=f"warm, s = {s:g}")
        ax.plot(grid, [spectral_radius(s, q, False) for q in grid], ":", color=f"C{k}")
    ax.axhline(1.0, color="k", linewidth=0.8)
    ax.axvline(0.5, color="k", linewidth=0.8, linestyle="--")
    ax.set_xlabel("q: fraction of a mode's error the capped solve leaves")
    ax.set_ylabel("spectral radius of one step")
    ax.set_title("Warm start (solid) against cold start (dotted)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    png = save_figure(fig, out / "spectral_radius.png")
    print(f"wrote {out / 'spectral_radius.csv'}, {out / 'jacobi_condition.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
