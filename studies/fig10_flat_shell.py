"""The paper's flat shell (§3.1.1, Fig. 10): mid-point deflection over the load for the full
and the modal formulations, on one Hex20 mesh.

Plate 1 x 0.8 m, 8 mm steel (E = 2.1e11 Pa, nu = 0.3, density 7850 kg/m^3), the four corner
edges (through the thickness) clamped, a transverse force of up to 7,500 N at the middle
(a line load through the thickness at the centre node column, consistent shares 1/6, 2/3,
1/6). Curves:

  full linear            K u = F
  full StVK              Newton on the total-Lagrangian StVK body, load step by load step
  modal (normal modes)   the paper's MODAL: fixed-boundary normal modes only
  Craig-Bampton          normal modes + constraint modes at the loaded nodes (ADAMS)
  CB + K_sigma (load)    eqs 7-8: geometric stiffness of the unit load's linear stress
  CB + K_sigma (modes)   eqs 9-11: geometric stiffness of each mode's linear stress
  CB + K_sigma (scaled)  the paper's alternative: (K_T - K_L) at a scaled mode shape
  reduced StVK           polynomial StVK forces on the CB basis + modal derivatives

    python -m studies.fig10_flat_shell --out flat-shell   # shell.md, shell.csv, shell.png (about 2 minutes)
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
import scipy.sparse.linalg as sla

import corotate as cr
from corotate.modal import ModalBody, craig_bampton
from corotate.modal.geometric_stiffness import (
    load_geometric_stiffness,
    mode_geometric_stiffness,
    scaled_mode_geometric_stiffness,
)
from corotate.modal.reduced_stvk import modal_derivatives, reduced_stvk_tensors

from ._common import output_folder, parser, pyplot, save_figure, write_csv

LX, LY, T = 1.0, 0.8, 0.008
MATERIAL = cr.Material(E=2.1e11, nu=0.3, density=7850.0)
FORCE = 7500.0


def shell(cells=(20, 16)):
    mesh = cr.box((LX, LY, T), cells=(cells[0], cells[1], 1), element="hex20")
    p = mesh.points
    corner = (np.isclose(p[:, 0], 0.0) | np.isclose(p[:, 0], LX)) & (np.isclose(p[:, 1], 0.0) | np.isclose(p[:, 1], LY))
    fixed = np.flatnonzero(corner)
    centre = np.flatnonzero(np.isclose(p[:, 0], LX / 2) & np.isclose(p[:, 1], LY / 2))
    centre = centre[np.argsort(p[centre, 2])]
    shares = np.array([1 / 6, 2 / 3, 1 / 6])  # a quadratic edge's consistent line-load shares
    load = np.zeros((mesh.n_nodes, 3))
    load[centre, 2] = -shares
    return mesh, fixed, centre, load


def full_curves(mesh, fixed, centre, load, levels):
    mid = centre[1]
    linear = cr.Body(mesh, MATERIAL, model="linear")
    sim = cr.Simulation(linear, solver=cr.Direct())
    sim.fix(fixed)
    sim.external_forces[:] = FORCE * load
    # The thin plate's round-off floor of the relative residual is ~1.3e-8: ask 1e-6.
    sim.solve_static(tolerance=1e-6)
    w_lin = -sim.displacements[mid, 2] * levels / FORCE
    stvk = cr.Body(mesh, MATERIAL, model="stvk")
    sim = cr.Simulation(stvk, solver=cr.Direct())
    sim.fix(fixed)
    w_nl = []
    for F in levels:
        sim.external_forces[:] = F * load
        sim.solve_static(load_steps=1, tolerance=1e-6, max_iterations=50)
        w_nl.append(-sim.displacements[mid, 2])
    return w_lin, np.array(w_nl)


def modal_curve(body: ModalBody, modal_unit_load, levels, mid, load_cases=False):
    """Mid-point deflection per load level (NaN from the first level without equilibrium)."""
    w = np.full(len(levels), np.nan)
    for k, F in enumerate(levels):
        if load_cases:
            body.load_amplitudes = [F]
        else:
            body.modal_forces[:] = F * modal_unit_load
        try:
            body.solve_static(load_steps=4, tolerance=1e-10, max_iterations=100)
        except RuntimeError as err:
            print(f"  no modal equilibrium at {F:.0f} N: {err}")
            break
        w[k] = -body.displacements([mid])[0, 2]
    return w


def modal_curves(mesh, fixed, centre, load, levels, n_modes):
    """The modal variants' mid-point deflections per load level (a dict of curves)."""
    mid = centre[1]
    stvk = cr.Body(mesh, MATERIAL, model="stvk")
    curves = {}
    t0 = time.perf_counter()
    normal = craig_bampton(stvk, fixed, n_modes=n_modes + 3)
    cb = craig_bampton(stvk, fixed, n_modes=n_modes, interface_nodes=centre)
    unit = load.ravel()
    curves["modal (normal modes)"] = modal_curve(ModalBody(normal), normal.vectors.T @ unit, levels, mid)
    curves["Craig-Bampton"] = modal_curve(ModalBody(cb), cb.vectors.T @ unit, levels, mid)

    loads, geometric = load_geometric_stiffness(stvk, cb, load[None])
    with_load = ModalBody(cb)
    with_load.set_load_cases(loads, geometric)
    curves["CB + K_sigma (load, eqs 7-8)"] = modal_curve(with_load, None, levels, mid, load_cases=True)
    A_modes = mode_geometric_stiffness(stvk, cb)
    curves["CB + K_sigma (modes, eqs 9-11)"] = modal_curve(
        ModalBody(cb, quadratic=A_modes), cb.vectors.T @ unit, levels, mid
    )
    A_scaled = scaled_mode_geometric_stiffness(stvk, cb)
    curves["CB + K_sigma (scaled-mode tangent)"] = modal_curve(
        ModalBody(cb, quadratic=A_scaled), cb.vectors.T @ unit, levels, mid
    )
    print(f"modal linear and K_sigma models: {time.perf_counter() - t0:.1f} s")

    t0 = time.perf_counter()
    # Enrich the basis with modal derivatives of the linear static shape and the first modes:
    # the membrane (in-plane) fields that a growing bending deflection drags along.
    free = np.setdiff1d(np.arange(3 * mesh.n_nodes), cb.fixed_dofs)
    K = stvk.stiffness_matrix().tocsc()
    static = np.zeros(3 * mesh.n_nodes)
    static[free] = sla.spsolve(K[free][:, free].tocsc(), unit[free])
    shapes = np.column_stack([static, normal.vectors[:, :3]])
    derivs = modal_derivatives(stvk, shapes, cb.fixed_dofs, [(0, 0), (1, 1), (2, 2), (3, 3), (1, 2), (0, 1)])
    rich = craig_bampton(stvk, fixed, n_modes=n_modes, interface_nodes=centre, extra_vectors=derivs)
    A, B = reduced_stvk_tensors(stvk, rich)
    poly = ModalBody(rich, quadratic=A, cubic=B)
    curves[f"reduced StVK ({rich.size} vectors)"] = modal_curve(poly, rich.vectors.T @ unit, levels, mid)
    print(f"reduced StVK: {time.perf_counter() - t0:.1f} s (basis {rich.size} vectors)")

    return curves


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "flat-shell")
    p.add_argument("--cells", type=int, nargs=2, default=(20, 16), help="Hex20 cells along x and y (even)")
    p.add_argument("--modes", type=int, default=12, help="fixed-boundary normal modes")
    p.add_argument("--levels", type=int, default=10, help="load levels up to 7,500 N")
    args = p.parse_args(argv)
    out = output_folder(args.out)

    mesh, fixed, centre, load = shell(tuple(args.cells))
    levels = FORCE * np.arange(1, args.levels + 1) / args.levels
    curves = {}
    t0 = time.perf_counter()
    curves["full linear"], curves["full StVK"] = full_curves(mesh, fixed, centre, load, levels)
    print(f"full models: {time.perf_counter() - t0:.1f} s ({3 * mesh.n_nodes} DOFs)")

    curves.update(modal_curves(mesh, fixed, centre, load, levels, args.modes))

    names = list(curves)
    header = "| F [N] | " + " | ".join(names) + " |"
    lines = [header, "|" + "---|" * (len(names) + 1)]
    for k, F in enumerate(levels):
        lines.append(f"| {F:.0f} | " + " | ".join(f"{1e3 * curves[n][k]:.2f}" for n in names) + " |")
    full = curves["full StVK"][-1]
    lines.append(
        "| vs full StVK at 7,500 N | " + " | ".join(f"{100 * (curves[n][-1] / full - 1):+.1f} %" for n in names) + " |"
    )
    table = "\n".join(lines)
    print("mid-point deflection [mm]\n" + table)
    (out / "shell.md").write_text(table + "\n")
    rows = ([F, *(float(curves[n][k]) for n in names)] for k, F in enumerate(levels))
    write_csv(out / "shell.csv", ["force_N"] + [f"{n} [m]" for n in names], rows)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    for name in names:
        style = "k-" if name.startswith("full") else "--"
        ax.plot(
            np.r_[0, 1e3 * curves[name]],
            np.r_[0, levels],
            style if name != "full linear" else "k:",
            marker="o",
            ms=3,
            label=name,
        )
    ax.set_xlabel("mid-point deflection [mm]")
    ax.set_ylabel("force [N]")
    ax.set_title(f"Flat shell with clamped corners (paper Fig. 10), Hex20 {args.cells[0]} x {args.cells[1]} x 1")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    png = save_figure(fig, out / "shell.png", dpi=120)
    print(f"wrote {out / 'shell.md'}, {out / 'shell.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
