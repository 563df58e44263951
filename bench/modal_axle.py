"""A U-shaped "axle" with two arms that turn as domains (the paper's §3.2 rear axle,
Figs. 13-14, on a small stand-in): modal, modal + a single rigid rotation, and modal +
partial rotation against the full co-rotational solution.

Steel (E = 2.1e11 Pa, nu = 0.3). A flat cross member (x in [0, 0.1], y in [0, 1], 20 mm thick)
joins two stiff arms (y in [0, 0.1] and [0.9, 1], 0.8 m long in x, 0.1 m high); the middle
of the cross member is clamped. Opposite vertical forces at the arm ends (the "wheels": down
on the left, up on the right) twist the cross member, so the arms pitch by about 10-15
degrees in opposite directions: the structure as a whole hardly turns, which is where a
single rigid-body rotation cannot help and rotating each arm as a domain can. Hex20 cells
of 0.1 x 0.1 x 0.02 m; 20 fixed-boundary normal modes.

    python bench/modal_axle.py [--out modal-axle]    # table on stdout, PNG with matplotlib
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import corotate as cr
from corotate.modal import PartialRotation, craig_bampton, least_squares_rotation
from corotate.picture import _pyplot

MATERIAL = cr.Material(E=2.1e11, nu=0.3, density=7850.0)
ARM, WIDTH, STEP, STRIP = 0.8, 1.0, 0.1, 0.02


def axle_mesh() -> cr.Mesh:
    """The U: cells of a 0.8 x 1 x 0.1 grid kept where they belong to an arm or (bottom
    layer only) to the cross member; unused nodes dropped."""
    grid = cr.box((ARM, WIDTH, 5 * STRIP), cells=(8, 10, 5), element="hex20")
    centres = grid.points[grid.cells].mean(axis=1)
    arm = (centres[:, 1] < STEP) | (centres[:, 1] > WIDTH - STEP)
    cross = (centres[:, 0] < STEP) & (centres[:, 2] < STRIP)
    cells = grid.cells[arm | cross]
    used, compact = np.unique(cells, return_inverse=True)
    return cr.Mesh(grid.points[used], compact.reshape(cells.shape), "hexahedron20")


def setup():
    """mesh, fixed nodes, the two arms' node sets, their tip (wheel) nodes and the unit
    load ((n, 3): -z on the left tip face, +z on the right)."""
    mesh = axle_mesh()
    p = mesh.points
    fixed = np.flatnonzero((np.abs(p[:, 1] - WIDTH / 2) <= STEP / 2 + 1e-9) & (p[:, 0] <= STEP + 1e-9))
    arms = [np.flatnonzero(p[:, 1] <= STEP + 1e-9), np.flatnonzero(p[:, 1] >= WIDTH - STEP - 1e-9)]
    tips = [a[np.isclose(p[a, 0], ARM)] for a in arms]
    load = np.zeros((mesh.n_nodes, 3))
    for tip, sign in zip(tips, (-1.0, 1.0)):
        load[tip, 2] = sign / tip.size
    return mesh, fixed, arms, tips, load


def arm_state(mesh, arms, tips, u):
    """Per arm: mean tip displacement (3,) and pitch angle [deg] (the arm's least-squares
    rotation about y)."""
    out = []
    for arm, tip in zip(arms, tips):
        R = least_squares_rotation(mesh.points[arm], mesh.points[arm] + u[arm])
        out.append((u[tip].mean(axis=0), np.degrees(np.arctan2(R[0, 2], R[0, 0]))))
    return out


def run(forces):
    mesh, fixed, arms, tips, load = setup()
    results = {
        name: [] for name in ("full co-rotational", "modal", "modal + rigid rotation", "modal + partial rotation")
    }
    sim = cr.Simulation(cr.Body(mesh, MATERIAL, model="corotational"), solver=cr.Direct())
    sim.fix(fixed)
    body = cr.Body(mesh, MATERIAL, model="linear")
    basis = craig_bampton(body, fixed, n_modes=20)
    top = 5 * STRIP
    # Four representative points per arm: its root and tip corners.
    reps = [
        [mesh.nearest_node(pt) for pt in ((STEP, y0, 0), (STEP, y1, top), (ARM, y0, 0), (ARM, y1, top))]
        for y0, y1 in ((0.0, STEP), (WIDTH - STEP, WIDTH))
    ]
    # The single rigid rotation: one domain, the whole body, points at its far corners.
    whole = [mesh.nearest_node(pt) for pt in ((0, 0, 0), (0, WIDTH, 0), (ARM, 0, top), (ARM, WIDTH, top))]
    rigid = PartialRotation(mesh.points, [np.arange(mesh.n_nodes)], [whole])
    partial = PartialRotation(mesh.points, arms, reps, blend_distance=0.05)
    q_unit = (basis.vectors.T @ load.ravel()) / basis.eigenvalues
    for F in forces:
        sim.external_forces[:] = F * load
        sim.solve_static(load_steps=2, tolerance=1e-6)  # round-off floor here: ~6e-8
        results["full co-rotational"].append(arm_state(mesh, arms, tips, sim.displacements))
        u = (basis.vectors @ (F * q_unit)).reshape(-1, 3)
        results["modal"].append(arm_state(mesh, arms, tips, u))
        results["modal + rigid rotation"].append(arm_state(mesh, arms, tips, rigid.apply(u)))
        results["modal + partial rotation"].append(arm_state(mesh, arms, tips, partial.apply(u)))
    return results


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="modal-axle", help="output folder (PNG)")
    parser.add_argument("--force", type=float, default=3.0e4, help="largest wheel force [N]")
    args = parser.parse_args(argv)
    forces = args.force * np.arange(1, 6) / 5
    results = run(forces)
    print("left arm (loaded down): wheel x and z displacement [mm], pitch [deg]")
    print("| F [kN] | " + " | ".join(results) + " |")
    print("|---" * (len(results) + 1) + "|")
    for k, F in enumerate(forces):
        cells = [f"{1e3 * r[k][0][0][0]:.1f}, {1e3 * r[k][0][0][2]:.1f}, {r[k][0][1]:.2f}" for r in results.values()]
        print(f"| {F / 1e3:.0f} | " + " | ".join(cells) + " |")
    try:
        plt = _pyplot()  # the package's matplotlib loader (Agg: files only)
    except ImportError as err:
        print(f"no plot: {err}")
        return 0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for name, r in results.items():
        x = [1e3 * s[0][0][0] for s in r]
        z = [1e3 * s[0][0][2] for s in r]
        ax.plot([0, *x], [0, *z], "k-o" if name.startswith("full") else "--o", ms=3, label=name)
    ax.set_xlabel("left wheel x displacement [mm]")
    ax.set_ylabel("left wheel z displacement [mm]")
    ax.set_title("U-shaped axle, arms pitching in opposite directions")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "axle.png", dpi=120)
    print(f"wrote {out / 'axle.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
