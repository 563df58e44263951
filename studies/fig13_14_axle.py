"""A U-shaped "axle" with two arms that turn as domains (the paper's §3.2 rear axle,
Figs. 13-14, on a small stand-in): modal, modal + a single rigid rotation, and modal +
partial rotation against the full co-rotational solution, for a wheel load and a side load.

Steel (E = 2.1e11 Pa, nu = 0.3). A flat cross member (x in [0, 0.1], y in [0, 1], 20 mm thick)
joins two stiff arms (y in [0, 0.1] and [0.9, 1], 0.8 m long in x, 0.1 m high); the middle
of the cross member is clamped. Hex20 cells of 0.1 x 0.1 x 0.02 m; 20 fixed-boundary normal
modes; each arm a domain (its root and tip corners the four points), blended over 5 cm.

Load case 1, "wheel": opposite vertical forces at the arm ends (the wheels: down on the left,
up on the right) twist the cross member, so the arms pitch by about 10-15 degrees in opposite
directions: the structure as a whole hardly turns, which is where a single rigid-body rotation
cannot help and rotating each arm as a domain can. The arm also rolls, and pitch and roll
together turn it about the vertical: the toe angle of Fig. 13, which a linear solution misses.
Load case 2, "side": an outward side force at the left wheel, at the cross member's height,
bends the cross member in its plane: the left arm toes out by 10-15 degrees (Fig. 14).

Measured per arm: the mean displacement of its end face (the wheel) and the angles of the
arm's least-squares rotation (intrinsic z-y-x angles): toe about the vertical z, pitch about y.

    python -m studies.fig13_14_axle --out axle    # wheel.csv, side.csv, axle.png (about 10 s)
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

import corotate as cr
from corotate.modal import ModalBody, PartialRotation, craig_bampton, least_squares_rotation

from ._common import output_folder, parser, pyplot, write_csv

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


VARIANTS = ("full co-rotational", "modal", "modal + rigid rotation", "modal + partial rotation")
CASES = {"wheel": 3.0e4, "side": 3.0e5}  # load case -> largest force [N]


def setup():
    """mesh, fixed nodes, the two arms' node sets, their tip (wheel) nodes and the unit
    loads ((n, 3)): "wheel" -z on the left tip face and +z on the right; "side" -y (outward)
    on the left tip face's nodes at the cross member's height."""
    mesh = axle_mesh()
    p = mesh.points
    fixed = np.flatnonzero((np.abs(p[:, 1] - WIDTH / 2) <= STEP / 2 + 1e-9) & (p[:, 0] <= STEP + 1e-9))
    arms = [np.flatnonzero(p[:, 1] <= STEP + 1e-9), np.flatnonzero(p[:, 1] >= WIDTH - STEP - 1e-9)]
    tips = [a[np.isclose(p[a, 0], ARM)] for a in arms]
    wheel = np.zeros((mesh.n_nodes, 3))
    for tip, sign in zip(tips, (-1.0, 1.0)):
        wheel[tip, 2] = sign / tip.size
    side = np.zeros((mesh.n_nodes, 3))
    low = tips[0][p[tips[0], 2] <= STRIP + 1e-9]  # in the cross member's plane: no twist
    side[low, 1] = -1.0 / low.size
    return mesh, fixed, arms, tips, {"wheel": wheel, "side": side}


def arm_state(mesh, arms, tips, u):
    """Per arm: mean tip displacement (3,) and (toe, pitch) [deg], the angles about z and y of
    the arm's least-squares rotation."""
    out = []
    for arm, tip in zip(arms, tips):
        R = least_squares_rotation(mesh.points[arm], mesh.points[arm] + u[arm])
        toe, pitch, _roll = Rotation.from_matrix(R).as_euler("ZYX", degrees=True)
        out.append((u[tip].mean(axis=0), toe, pitch))
    return out


def run(forces, case="wheel"):
    """{variant: [arm_state per force]} for load case "wheel" or "side"."""
    mesh, fixed, arms, tips, loads = setup()
    load = loads[case]
    results: dict[str, list] = {name: [] for name in VARIANTS}
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
    turned = ModalBody(basis, partial_rotation=partial)
    q_unit = (basis.vectors.T @ load.ravel()) / basis.eigenvalues  # the linear static answer
    for F in forces:
        sim.external_forces[:] = F * load
        sim.solve_static(load_steps=3, tolerance=1e-6)  # round-off floor here: ~6e-8
        results["full co-rotational"].append(arm_state(mesh, arms, tips, sim.displacements))
        u = (basis.vectors @ (F * q_unit)).reshape(-1, 3)
        results["modal"].append(arm_state(mesh, arms, tips, u))
        results["modal + rigid rotation"].append(arm_state(mesh, arms, tips, rigid.apply(u)))
        turned.q[:] = F * q_unit  # recovered with the partial rotation, in the core
        results["modal + partial rotation"].append(arm_state(mesh, arms, tips, turned.displacements()))
    return results


def print_table(case, forces, results) -> None:
    print(f"load case {case!r}, left wheel: x, y, z displacement [mm]; toe, pitch [deg]")
    print("| F [kN] | " + " | ".join(results) + " |")
    print("|---" * (len(results) + 1) + "|")
    for k, F in enumerate(forces):
        cells = []
        for r in results.values():
            (x, y, z), toe, pitch = r[k][0]
            cells.append(f"{1e3 * x:.1f}, {1e3 * y:.1f}, {1e3 * z:.1f}; {toe:.2f}, {pitch:.2f}")
        print(f"| {F / 1e3:.0f} | " + " | ".join(cells) + " |")


def plot(out: Path, runs) -> Path:
    """Three panels: wheel travel vs toe (Fig. 13), the side-loaded wheel's x vs toe (Fig. 14), and
    the wheel's path in x-z under the wheel load."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.5))

    def toe(s):
        return s[1]

    def wheel_mm(axis):
        return lambda s: 1e3 * s[0][axis]

    panels = (
        ("wheel", toe, wheel_mm(2), "toe [deg]", "wheel z [mm]", "(a) wheel load: travel vs toe"),
        ("side", toe, wheel_mm(0), "toe [deg]", "wheel x [mm]", "(b) side load: wheel x vs toe"),
        ("wheel", wheel_mm(0), wheel_mm(2), "wheel x [mm]", "wheel z [mm]", "(c) wheel load: x-z path"),
    )
    for ax, (case, fx, fy, xlabel, ylabel, title) in zip(axes, panels):
        for name, r in runs[case].items():
            states = [s[0] for s in r]  # the left arm
            style = "k-o" if name.startswith("full") else "--o"
            ax.plot([0, *map(fx, states)], [0, *map(fy, states)], style, ms=3, label=name)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("U-shaped axle, left wheel: modal variants against the full co-rotational solution")
    fig.tight_layout()
    fig.savefig(out / "axle.png", dpi=110)
    return out / "axle.png"


def write_table(path: Path, forces, results) -> Path:
    """One row per force: F [N], then per variant the left wheel's x, y, z [m], toe and pitch [deg]."""
    header = ["force_N"] + [f"{name}: {q}" for name in results for q in ("x_m", "y_m", "z_m", "toe_deg", "pitch_deg")]
    rows = []
    for k, F in enumerate(forces):
        row = [float(F)]
        for r in results.values():
            (x, y, z), toe, pitch = r[k][0]
            row += [float(x), float(y), float(z), float(toe), float(pitch)]
        rows.append(row)
    return write_csv(path, header, rows)


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "axle")
    p.add_argument("--levels", type=int, default=5, help="load levels per case (default 5)")
    args = p.parse_args(argv)
    out = output_folder(args.out)
    runs = {}
    for case, largest in CASES.items():
        forces = largest * np.arange(1, args.levels + 1) / args.levels
        runs[case] = run(forces, case)
        print_table(case, forces, runs[case])
        write_table(out / f"{case}.csv", forces, runs[case])
    path = plot(out, runs)
    print(f"wrote {out / 'wheel.csv'}, {out / 'side.csv'} and {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
