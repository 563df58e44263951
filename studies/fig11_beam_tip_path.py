"""Partial rotation of displacements (§3.2, Fig. 11): the tip path of a cantilever in its
first mode, modal with and without the rotation, against the full co-rotational solution.

Hex20 cantilever 10 x 1 x 0.5 m (E = 1e7 Pa, nu = 0), clamped at x = 0, tip loads up to
PL^2/EI = 2 (tip rotation ~45 degrees). The modal path scales the first mode; the rotated one
turns each displacement by half the least-squares rotation of four representative points
(corners at x = 3 and x = 10).

    python -m studies.fig11_beam_tip_path --out beam-tip-path   # full.csv, modal.csv, beam_tip_path.png
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import corotate as cr
from corotate.modal import PartialRotation, craig_bampton

from ._common import output_folder, parser, pyplot, save_figure, write_csv

L, B, H = 10.0, 1.0, 0.5
MATERIAL = cr.Material(E=1e7, nu=0.0, density=1000.0)


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "beam-tip-path")
    p.add_argument("--levels", type=int, default=20, help="load levels of the full solution (default 20)")
    args = p.parse_args(argv)
    out = output_folder(args.out)
    mesh = cr.beam(L, B, H, cells=(10, 1, 1), element="hex20")
    fixed = mesh.nodes_on_plane("x", 0.0)
    tip = mesh.nodes_on_plane("x", L)
    weight = np.full(tip.size, 1.0 / tip.size)  # mean of the tip face nodes

    sim = cr.Simulation(cr.Body(mesh, MATERIAL, model="corotational"), solver=cr.Direct())
    sim.fix(fixed)
    EI = MATERIAL.E * B * H**3 / 12
    full = [(0.0, 0.0)]
    for load in np.linspace(2.0 / args.levels, 2.0, args.levels) * EI / L**2:
        sim.external_forces[tip, 2] = load / tip.size
        sim.solve_static(load_steps=2, tolerance=1e-8)
        full.append(tuple(weight @ sim.displacements[tip][:, [0, 2]]))
    full_path = np.array(full)

    basis = craig_bampton(cr.Body(mesh, MATERIAL, model="linear"), fixed, n_modes=1)
    mode = basis.vectors[:, 0].reshape(-1, 3)
    mode *= np.sign(weight @ mode[tip, 2])
    corners = [mesh.nearest_node(p) for p in ((3.0, 0, 0), (3.0, B, H), (L, 0, 0), (L, B, H))]
    rotation = PartialRotation(mesh.points, [np.arange(mesh.n_nodes)], [corners])
    amplitudes = np.linspace(0.0, 1.1, 45) * full_path[-1, 1] / (weight @ mode[tip, 2])
    modal = np.array([weight @ (a * mode)[tip][:, [0, 2]] for a in amplitudes])
    rotated = np.array([weight @ rotation.apply(a * mode)[tip][:, [0, 2]] for a in amplitudes])

    print("tip z [m] | full co-rotational x [m] | modal x | modal + partial rotation x")
    for x, z in full_path[1::4]:
        print(
            f"{z:9.3f} | {x:24.4f} | {np.interp(z, modal[:, 1], modal[:, 0]):7.4f} | "
            f"{np.interp(z, rotated[:, 1], rotated[:, 0]):8.4f}"
        )
    write_csv(out / "full.csv", ["tip_x_m", "tip_z_m"], full_path.tolist())
    write_csv(
        out / "modal.csv",
        ["modal_tip_x_m", "modal_tip_z_m", "rotated_tip_x_m", "rotated_tip_z_m"],
        np.column_stack([modal, rotated]).tolist(),
    )
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 6))
    ax.plot(L + full_path[:, 0], full_path[:, 1], "k-o", ms=3, label="full co-rotational")
    ax.plot(L + modal[:, 0], modal[:, 1], "--", label="modal (first mode)")
    ax.plot(L + rotated[:, 0], rotated[:, 1], "--", label="modal + partial rotation")
    ax.set_xlabel("tip x [m]")
    ax.set_ylabel("tip z [m]")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlim(7.0, 10.5)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("Cantilever tip path (paper Fig. 11)")
    png = save_figure(fig, out / "beam_tip_path.png", dpi=120)
    print(f"wrote {out / 'full.csv'}, {out / 'modal.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
