"""The paper's force-feedback example (section 2.2.3, Fig. 8) and a bending counterpart: the
reaction force at a prescribed beam end, computed four ways on the same tet mesh.

Beam 5 x 1 x 1 m along x, E = 1e7 Pa, nu = 0.3; the face x = 0 is clamped and the nodes of the
face x = 5 (the tool) are moved to prescribed positions; static equilibrium at each level.
  - "pull": the end face moves along x by up to the beam's length (the length doubles);
  - "bend": the end face moves along z by up to 40 % of the length (x and y held).
Curves, the force the body exerts on the tool along the motion (its negative: what the
device must push with):
  linear        linear FEM equilibrium, linear reaction;
  corotational  co-rotational equilibrium, co-rotational reaction (eq. 3);
  averaged      co-rotational equilibrium, averaged-stiffness reaction (eq. 5) of the elements
                around the tool: the paper's use, a co-rotational simulation with the
                feedback corrected where the device touches it;
  stvk          full nonlinear St. Venant-Kirchhoff equilibrium and reaction (the reference).

    python -m studies.fig8_force_elongation --out force-elongation   # pull.csv, bend.csv, force_elongation.png
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from corotate import Body, Direct, HapticFeedback, Material, Simulation, beam

from ._common import output_folder, parser, pyplot, write_csv

CURVES = ("linear", "corotational", "averaged", "stvk")
LENGTH = 5.0
MATERIAL = Material(E=1e7, nu=0.3, density=1000.0)


def force_curves(case: str = "pull", cells: tuple[int, int, int] = (20, 4, 4), levels: int = 10) -> dict:
    """Reaction-force curves of one case ("pull" or "bend").

    returns {"displacement": (levels,) prescribed end displacement [m], and per curve name
    (levels,) reaction force along the motion [N], "tets": elements, "tool_elements": elements
    around the tool}"""
    if case not in ("pull", "bend"):
        raise ValueError(f"unknown case {case!r}; choose 'pull' or 'bend'")
    mesh = beam(LENGTH, 1.0, 1.0, cells=cells, element="tet4")
    clamped, tool = mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", LENGTH)
    axis = 0 if case == "pull" else 2
    full = LENGTH if case == "pull" else 0.4 * LENGTH
    amounts = full * np.arange(1, levels + 1) / levels
    result: dict = {"displacement": amounts, "tets": mesh.n_cells}
    feedback = {m: HapticFeedback(Body(mesh, MATERIAL), tool, m) for m in ("linear", "corotational", "averaged")}
    result["tool_elements"] = feedback["averaged"].num_elements
    for model in ("linear", "corotational", "stvk"):
        sim = Simulation(Body(mesh, MATERIAL, model=model), solver=Direct())
        sim.fix(np.concatenate([clamped, tool]))
        curves: dict[str, list[float]] = {}
        for amount in amounts:  # each level starts from the previous equilibrium
            target = mesh.points.copy()
            target[tool, axis] += amount
            sim.solve_static(load_steps=4, tolerance=1e-9, prescribed=target)
            methods = {"linear": ["linear"], "corotational": ["corotational", "averaged"], "stvk": ["averaged"]}[model]
            for method in methods:
                name = "stvk" if model == "stvk" else method
                force = -feedback[method].total_force(sim.positions)[axis]
                curves.setdefault(name, []).append(float(force))
        for name, values in curves.items():
            result[name] = np.array(values)
    return result


def write_table(result: dict, path: Path) -> Path:
    """One row per level: prescribed displacement [m], then the reaction of each curve [N]."""
    rows = ([d, *(float(result[c][k]) for c in CURVES)] for k, d in enumerate(result["displacement"]))
    return write_csv(path, ["displacement_m"] + [f"{c}_N" for c in CURVES], rows)


def plot(results: dict[str, dict], path: Path) -> Path:
    """Fig. 8 (pull) beside the bending case: reaction force against prescribed displacement."""
    plt = pyplot()
    labels = {
        "linear": "linear",
        "corotational": "co-rotational (eq. 3)",
        "averaged": "co-rotational + averaged stiffness (eq. 5)",
        "stvk": "full nonlinear (StVK)",
    }
    styles = {"linear": "k--", "corotational": "C0-o", "averaged": "C2-^", "stvk": "C3-s"}
    fig, axes = plt.subplots(1, len(results), figsize=(6.5 * len(results), 4.5), constrained_layout=True)
    for ax, (case, result) in zip(np.atleast_1d(axes), results.items()):
        d = np.concatenate([[0.0], result["displacement"]])
        for c in CURVES:
            ax.plot(d, np.concatenate([[0.0], result[c]]) / 1e6, styles[c], label=labels[c], markersize=3)
        ax.set_xlabel("prescribed end displacement along " + ("x" if case == "pull" else "z") + " [m]")
        ax.set_ylabel("reaction force [MN]")
        ax.set_title(
            ("pulled end (Fig. 8)" if case == "pull" else "bent end")
            + f": {result['tets']} tets, {result['tool_elements']} around the tool"
        )
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].legend()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "force-elongation")
    p.add_argument("--cells", type=int, nargs=3, default=(20, 4, 4), help="cubes per direction (default 20 4 4)")
    p.add_argument("--levels", type=int, default=10, help="displacement levels (default 10)")
    args = p.parse_args(argv)
    out = output_folder(args.out)
    results = {}
    for case in ("pull", "bend"):
        result = force_curves(case, tuple(args.cells), args.levels)
        results[case] = result
        write_table(result, out / f"{case}.csv")
        print(f"{case}: {result['tets']} tets, {result['tool_elements']} around the tool; at the last level:")
        reference = result["stvk"]
        for c in CURVES:
            gap = np.max(np.abs(result[c] - reference)) / np.max(np.abs(reference))
            print(f"  {c:13s} {result[c][-1] / 1e6:9.4f} MN   max distance from StVK {100 * gap:6.1f} % of its peak")
    png = plot(results, out / "force_elongation.png")
    print(f"wrote {out / 'pull.csv'}, {out / 'bend.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
