"""The paper's Table 1 (§2.2.2): the dog model, five steps of 0.01 s per frame, timed for
(a) the FE mesh only, (b) + the embedded surface vertices, (c) + their normals, (d) + an
off-screen render of the shaded surface to an image, (e) + a texture on it.

The scene (built by this script; the armadillo is read from ../shared/data and never
written into the repository) stands in for the paper's dog (700 tets, 314 nodes; 12,520
vertices, 24,835 faces):
- cage: fTetWild's tetrahedralization of the armadillo's boundary at about 700 tets
  (and 10x and 100x that), through corotate.tetrahedralize (extra corotate-fem[mesh]);
- render surface: the armadillo's boundary (1,053 vertices, 2,102 faces) after one step of
  Loop subdivision and a centroid split: 12,614 vertices, 25,224 faces;
- as the armadillo demo of Kugelstadt et al. (the data's origin): scaled by 0.1 (about
  0.3 m tall), E = 1 MPa, nu = 0.33, 1000 kg/m^3, gravity -9.81 m/s^2 along -y, the cage
  nodes within 4 cm of the point (1.1128, 1.7149, -0.6512) * 0.1 fixed (the demo fixes
  2 cm of its finer mesh), starting at rest; co-rotational FEM, linearised backward Euler.
  Solvers (--solvers, one per scale): "default" is corotate's default cr.PCG() (capped at 20
  iterations, warm-started; its "auto" preconditioner is the turned reference factor below
  6,000 unknowns, to 1e-2, and the two-level cycle above, to 2e-2), "two_level" the same
  with the two-level preconditioner at every size, "direct" a Cholesky factorization every step, "pcg" the
  two-level PCG run to 1e-6 (converged).

Accuracy: for every scale the script also runs the timed solver and a tight reference
(two-level PCG to 1e-9) over the same frames, untimed, and prints how far the tip (the cage
node farthest from the fixed point) and the centroid stray from the reference over the run,
as a percentage of how far they travel.

Rendering (d, e): PyVista/VTK off-screen (on a machine without a display: EGL with Mesa's
llvmpipe, i.e. software OpenGL), 640 x 480, smooth shading from the embedded normals; the
texture is a 512 x 512 checkerboard on spherical texture coordinates. Needs the extras
corotate-fem[mesh] (pytetwild, pyvista) for the cage and the render; without pyvista the
rows (d) and (e) are skipped.

    python -m studies.table1_dog --data ../shared/data/armadillo_4k.vtu --out table1
    taskset -c 1 python -m studies.table1_dog --scales 1,10,100 --frames 100,20,5
    taskset -c 1 python -m studies.table1_dog --scales 1 --frames 100 --solvers default --phases 1000

(--phases: no table, only the medians of a step's assembly, solve and whole call over that
many single steps from rest, and the CG iterations per step, printed and written to
OUT/phases.json.)

The armadillo is read from --data (default: ../shared/data/armadillo_4k.vtu beside the
clone). Prints the table, writes OUT/table1.md, OUT/table1.json, OUT/table1.csv, OUT/table1_render.png (what rows (d)
and (e) draw, at t = 1.5 s and 3 s, of the first scale) and OUT/table1.png (ratio and F/s
next to the paper's E8500 column).
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

import corotate as cr
from corotate.meshing import mesher_available

from ._common import ARMADILLO, mesh_file, output_folder, parser, pyplot, write_csv, write_json

# The paper draws in every row (on a GPU): FE mesh, vertices, the shaded surface (our d), textured.
PAPER_E8500 = {"a": (5.20, 104), "b": (3.05, 61), "d": (2.47, 49), "e": (1.63, 33)}
ROWS = {
    "a": "FE mesh only",
    "b": "+ embedded vertices",
    "c": "+ normals",
    "d": "+ shaded surface rendered",
    "e": "+ texture",
}
PAPER_ROW = {"a": "FE-mesh", "b": "Vertices", "d": "Surface", "e": "Texture"}
SCALE = 0.1
ANCHOR = np.array([1.1128, 1.7149, -0.6512]) * SCALE


def build_scene(data: Path, cells: int, cache: Path) -> tuple[cr.Mesh, cr.Mesh]:
    """The cage (about `cells` tets) and the render surface, cached in `cache` (outside the repo)."""
    volume = cr.read_mesh(data)
    volume = cr.Mesh(volume.points * SCALE, volume.cells, "tetra")
    boundary = cr.boundary_surface(volume)
    render = cr.split_at_centroids(cr.loop_subdivide(boundary))
    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"cage_{cells}.vtu"
    if path.exists():
        cage = cr.read_mesh(path)
    else:
        t0 = time.perf_counter()
        # Coarse cages need room to leave the surface's detail out (see corotate.tetrahedralize).
        envelope = 1.5e-2 if cells <= 1000 else 5e-3 if cells <= 10000 else 2e-3
        cage = cr.tetrahedralize(boundary, target_cells=cells, envelope=envelope)
        print(f"  tetrahedralized to {cage.n_cells} tets in {time.perf_counter() - t0:.1f} s")
        cr.write_mesh(path, cage)
    return cage, render


def spherical_uv(points: np.ndarray) -> np.ndarray:
    d = points - points.mean(axis=0)
    r = np.linalg.norm(d, axis=1)
    u = 0.5 + np.arctan2(d[:, 2], d[:, 0]) / (2 * np.pi)
    v = 0.5 + np.arcsin(np.clip(d[:, 1] / np.maximum(r, 1e-12), -1, 1)) / np.pi
    return np.column_stack([u, v])


class Renderer:
    """An off-screen PyVista scene of the surface whose points and normals are the
    EmbeddedSurface's arrays (updated in place, marked modified each frame)."""

    def __init__(self, surface: cr.EmbeddedSurface, textured: bool) -> None:
        import pyvista as pv

        faces = np.column_stack([np.full(surface.n_triangles, 3), surface.mesh.cells]).ravel()
        self.poly = pv.PolyData(surface.positions, faces)  # shares the positions buffer
        self.poly.point_data["Normals"] = surface.normals
        self.poly.point_data.active_normals_name = "Normals"
        self.plotter = pv.Plotter(off_screen=True, window_size=(640, 480))
        kwargs = {"smooth_shading": True, "color": "tan"}
        if textured:
            self.poly.active_texture_coordinates = spherical_uv(surface.mesh.points)
            i, j = np.indices((512, 512)) // 32
            checker = ((i + j) % 2).astype(np.uint8)
            image = np.stack([200 * checker + 40, 120 * checker + 60, 60 + 0 * checker], axis=-1).astype(np.uint8)
            kwargs = {"smooth_shading": True, "texture": pv.Texture(image)}
        self.plotter.add_mesh(self.poly, **kwargs)
        self.plotter.camera_position = "xy"
        self.surface = surface

    def draw(self) -> np.ndarray:
        self.poly.points = self.surface.positions  # the same buffer: no copy, marks it modified
        self.poly.point_data["Normals"] = self.surface.normals
        self.plotter.render()
        return self.plotter.screenshot(None, return_img=True)

    def close(self) -> None:
        self.plotter.close()


def frame(sim: cr.Simulation, surface: cr.EmbeddedSurface, mode: str, renderer: Renderer | None) -> None:
    """One frame of row `mode`: five steps, then what the row adds."""
    sim.step(5)
    if mode != "a":
        surface.update(sim, normals="none" if mode == "b" else "area")
    if renderer is not None:
        renderer.draw()


SOLVERS = {
    "default": cr.PCG,  # corotate's default: capped at 20 iterations, its preconditioner's tolerance
    "two_level": lambda: cr.PCG(preconditioner="two_level"),  # the default before "auto"
    "direct": cr.Direct,
    "pcg": lambda: cr.PCG(tolerance=1e-6, max_iterations=500),  # converged
    "reference": lambda: cr.PCG(tolerance=1e-9, max_iterations=2000),  # for the deviation only
}


def make_solver(solver: str) -> cr.PCG | cr.Direct:
    return SOLVERS[solver]()


def scene(cage: cr.Mesh, render: cr.Mesh) -> tuple[cr.Body, np.ndarray, cr.EmbeddedSurface]:
    """The hanging armadillo: its body, the fixed nodes and the embedded render surface."""
    body = cr.Body(cage, cr.Material(E=1e6, nu=0.33, density=1000.0))
    fixed = cage.nodes_where(lambda p: np.linalg.norm(p - ANCHOR, axis=1) < 0.04)
    if len(fixed) < 3:
        fixed = np.argsort(np.linalg.norm(cage.points - ANCHOR, axis=1))[:3]
    return body, fixed, cr.EmbeddedSurface(body, render.points, render.cells, max_outside_distance=1.0)


def at_rest(body: cr.Body, fixed: np.ndarray, solver: str) -> cr.Simulation:
    sim = cr.Simulation(body, dt=0.01, gravity=(0, -9.81, 0), solver=make_solver(solver))
    sim.fix(fixed)
    return sim


def render_frames(cage: cr.Mesh, render: cr.Mesh, solver: str, out: Path) -> Path:
    """OUT/table1_render.png: what rows (d) and (e) draw, at t = 1.5 s and 3 s."""
    plt = pyplot()
    body, fixed, surface = scene(cage, render)
    sim = at_rest(body, fixed, solver)
    renderers = {m: Renderer(surface, textured=m == "e") for m in "de"}
    fig, axes = plt.subplots(2, 2, figsize=(9, 7))
    for row, t_end in enumerate((1.5, 3.0)):
        while sim.time < t_end - 1e-9:
            sim.step(5)
        surface.update(sim, normals="area")
        for col, mode in enumerate("de"):
            axes[row, col].imshow(renderers[mode].draw())
            axes[row, col].set_title(f"({mode}) {ROWS[mode]}, t = {sim.time:.1f} s", fontsize=9)
            axes[row, col].axis("off")
    for renderer in renderers.values():
        renderer.close()
    path = out / "table1_render.png"
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def run(
    cage: cr.Mesh, render: cr.Mesh, frames: int, modes: list[str], solver: str, repeats: int
) -> dict[str, dict[str, float]]:
    """Times `frames` frames of each mode, `repeats` times with the modes interleaved (the
    machine is shared: a slow spell then hits every mode alike); the median wall time counts."""
    body, fixed, surface = scene(cage, render)
    results: dict[str, dict[str, float]] = {"_report": dict(surface.report, fixed=len(fixed))}
    renderers = {m: Renderer(surface, textured=m == "e") for m in modes if m in "de"}
    walls: dict[str, list[float]] = {m: [] for m in modes}
    for _ in range(repeats):
        for mode in modes:
            sim = at_rest(body, fixed, solver)
            renderer = renderers.get(mode)
            frame(sim, surface, mode, renderer)  # warm-up (first factorization, GL buffers): not timed
            t0 = time.perf_counter()
            for _ in range(frames):
                frame(sim, surface, mode, renderer)
            walls[mode].append(time.perf_counter() - t0)
    for renderer in renderers.values():
        renderer.close()
    for mode in modes:
        wall = float(np.median(walls[mode]))
        results[mode] = {"ratio": frames * 0.05 / wall, "fps": frames / wall, "wall": wall}
        print(f"    ({mode}) {ROWS[mode]:<28} ratio {results[mode]['ratio']:7.2f}  F/s {results[mode]['fps']:8.1f}")
    return results


def trajectory(cage: cr.Mesh, render: cr.Mesh, frames: int, solver: str) -> tuple[np.ndarray, np.ndarray]:
    """(tip, centroid) positions after each frame, (frames + 1, 3) each, from the rest state."""
    body, fixed, _ = scene(cage, render)
    sim = at_rest(body, fixed, solver)
    tip = int(np.argmax(np.linalg.norm(cage.points - ANCHOR, axis=1)))
    tips, centroids = [sim.positions[tip].copy()], [sim.positions.mean(axis=0)]
    for _ in range(frames):
        sim.step(5)
        tips.append(sim.positions[tip].copy())
        centroids.append(sim.positions.mean(axis=0))
    return np.array(tips), np.array(centroids)


def deviation(cage: cr.Mesh, render: cr.Mesh, frames: int, solver: str) -> dict[str, float]:
    """How far the tip and the centroid of a run with `solver` stray from the reference
    (two-level PCG to 1e-9) over `frames` frames: the largest distance, in % of the largest
    distance the reference travels from its start."""
    result = {}
    for name, run, ref in zip(
        ("tip", "centroid"), trajectory(cage, render, frames, solver), trajectory(cage, render, frames, "reference")
    ):
        travel = np.linalg.norm(ref - ref[0], axis=1).max()
        result[f"{name}_deviation_percent"] = float(100 * np.linalg.norm(run - ref, axis=1).max() / travel)
        result[f"{name}_travel_m"] = float(travel)
    return result


def phases(cage: cr.Mesh, render: cr.Mesh, steps: int, solver: str) -> dict[str, float]:
    """Medians over `steps` single steps from rest of the step's phases (sim.stats: the
    assembly and the solve, in ms), the whole step() call and the CG iterations per step."""
    body, fixed, _ = scene(cage, render)
    sim = at_rest(body, fixed, solver)
    assembly, solve, call, iterations = [], [], [], []
    for _ in range(steps):
        t0 = time.perf_counter()
        sim.step(1)
        call.append(1e3 * (time.perf_counter() - t0))
        stats = sim.stats
        assembly.append(stats["assembly_ms"])
        solve.append(stats["solve_ms"])
        iterations.append(stats["iterations"])
    return {
        "assembly_ms": float(np.median(assembly)),
        "solve_ms": float(np.median(solve)),
        "step_call_ms": float(np.median(call)),
        "iterations": float(np.mean(iterations)),
    }


def plot(table: dict, out: Path) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    rows = list(ROWS)
    xs = np.arange(len(rows))
    width = 0.8 / (len(table) + 1)
    for ax, key, label in zip(axes, ("ratio", "fps"), ("real-time ratio", "frames per second")):
        paper = [PAPER_E8500[r][0 if key == "ratio" else 1] if r in PAPER_E8500 else np.nan for r in rows]
        ax.bar(xs - 0.4 + width / 2, paper, width, label="paper, E8500 / 8800 GT (2008)", color="0.6")
        for i, (name, res) in enumerate(table.items()):
            vals = [res[r][key] if r in res else np.nan for r in rows]
            ax.bar(xs - 0.4 + width * (i + 1.5), vals, width, label=name)
        ax.set_yscale("log")
        ax.set_xticks(xs, [f"({r}) {ROWS[r]}" for r in rows], rotation=20, ha="right", fontsize=8)
        ax.set_ylabel(label)
        ax.axhline(1.0 if key == "ratio" else 60, color="k", linewidth=0.8, linestyle="--")
    # One legend for both panels, below them: inside, it covered the tallest bars.
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, -0.16))
    fig.suptitle("Table 1: dog/armadillo, 5 steps of 0.01 s per frame, one thread")
    path = out / "table1.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def _parser():
    p = parser(__doc__, "table1")
    p.add_argument("--data", default=str(ARMADILLO), help=f"the armadillo tet mesh (default {ARMADILLO})")
    p.add_argument("--scales", default="1,10,100", help="cage sizes as multiples of 700 tets")
    p.add_argument("--frames", default="100,20,4", help="frames timed per scale")
    p.add_argument("--modes", default="abcde", help="rows to time (default abcde)")
    p.add_argument("--repeats", type=int, default=3, help="interleaved repeats per mode (median; default 3)")
    p.add_argument(
        "--solvers",
        default="default,pcg,pcg",
        help="linear solver per scale: default (cr.PCG()), two_level (cr.PCG() with the two-level preconditioner), "
        "direct (Cholesky each step) or pcg (two-level PCG to 1e-6)",
    )
    p.add_argument("--from-json", help="redo the table and plot from this table1.json without timing")
    p.add_argument(
        "--phases",
        type=int,
        metavar="STEPS",
        help="instead of the table: the medians of the assembly, the solve and the whole step() call over "
        "STEPS single steps (and CG iterations per step) for each scale",
    )
    return p


def write_tables(table: dict, out: Path) -> str:
    """OUT/table1.md (the markdown table and the accuracy lines), OUT/table1.json (everything
    measured), OUT/table1.csv (one row per scene and row: ratio and frames per second) and
    OUT/table1.png; returns the markdown."""
    lines = ["| row | paper (E8500) | ratio | F/s | " + " | ".join(f"{n}: ratio | F/s" for n in table) + " |"]
    lines.append("| --- " * (4 + 2 * len(table)) + "|")
    for r in ROWS:
        paper = PAPER_E8500.get(r, ("-", "-"))
        cells = [f"{t[r]['ratio']:.3g} | {t[r]['fps']:.3g}" if r in t else "- | -" for t in table.values()]
        row = f"| ({r}) {ROWS[r]} | {PAPER_ROW.get(r, '-')} | {paper[0]} | {paper[1]} | "
        lines.append(row + " | ".join(cells) + " |")
    lines.append("")
    for name, t in table.items():
        if "_accuracy" in t:
            acc = t["_accuracy"]
            lines.append(
                f"{name}: off the converged motion (two-level PCG to 1e-9) by at most "
                f"{acc['tip_deviation_percent']:.3f} % (tip) and {acc['centroid_deviation_percent']:.3f} % "
                "(centroid) of their travel"
            )
    text = "\n".join(lines)
    (out / "table1.md").write_text(text + "\n")
    write_json(out / "table1.json", table)
    rows = [[name, f"({r}) {ROWS[r]}", t[r]["ratio"], t[r]["fps"]] for name, t in table.items() for r in ROWS if r in t]
    write_csv(out / "table1.csv", ["scene", "row", "real_time_ratio", "frames_per_second"], rows)
    plot(table, out)
    return text


def main(argv: Sequence[str] | None = None) -> int:
    p = _parser()
    args = p.parse_args(argv)
    out = output_folder(args.out)
    scales = [int(s) for s in args.scales.split(",")]
    frames = [int(f) for f in args.frames.split(",")]
    solvers = args.solvers.split(",")
    choices = [s for s in SOLVERS if s != "reference"]
    if any(s not in choices for s in solvers) or not len(scales) == len(frames) == len(solvers):
        p.error(f"--scales, --frames and --solvers need one entry each per scale; solvers: {', '.join(choices)}")
    table: dict[str, dict] = {}
    if args.from_json:  # only the table and the plot, from an earlier run's results
        table = json.loads(Path(args.from_json).read_text())
        scales = []
    else:
        data = mesh_file(p, args.data)
        if not mesher_available():
            p.error("the cages are made by corotate.tetrahedralize (fTetWild): pip install 'corotate-fem[mesh]'")
    modes = list(args.modes)
    try:
        import pyvista  # noqa: F401
    except ImportError:
        print("pyvista is not installed: rows (d) and (e) are skipped (pip install 'corotate-fem[mesh]')")
        modes = [m for m in modes if m not in "de"]
    if args.phases:
        measured = {}
        for scale, solver in zip(scales, solvers):
            cage, render = build_scene(data, 700 * scale, out / "scene")
            ph = measured[f"{cage.n_cells} tets, {solver}"] = phases(cage, render, args.phases, solver)
            print(
                f"{cage.n_cells} tets, {solver}, {args.phases} steps: assembly {ph['assembly_ms']:.4f} ms",
                f"({1e6 * ph['assembly_ms'] / cage.n_cells:.0f} ns per tet), solve {ph['solve_ms']:.4f} ms,",
                f"step() {ph['step_call_ms']:.4f} ms, {ph['iterations']:.2f} CG iterations per step",
            )
        print(f"wrote {write_json(out / 'phases.json', measured)}")
        return 0
    for scale, n_frames, solver in zip(scales, frames, solvers):
        cage, render = build_scene(data, 700 * scale, out / "scene")
        name = f"{cage.n_cells} tets, {solver}"
        print(
            f"{name}, {cage.n_nodes} nodes; surface {render.n_nodes} vertices, {render.n_cells} faces;",
            f"{n_frames} frames",
        )
        table[name] = run(cage, render, n_frames, modes, solver, args.repeats)
        print(f"    surface: {table[name]['_report']}")
        table[name]["_accuracy"] = deviation(cage, render, n_frames, solver)
        acc = table[name]["_accuracy"]
        print(
            f"    off the reference over {n_frames} frames: tip {acc['tip_deviation_percent']:.3f} % of its",
            f"{acc['tip_travel_m']:.3f} m travel, centroid {acc['centroid_deviation_percent']:.3f} % of",
            f"{acc['centroid_travel_m']:.3f} m",
        )
        if scale == scales[0] and "d" in modes and "e" in modes:
            print(f"wrote {render_frames(cage, render, solver, out)}")
    print(write_tables(table, out))
    print(f"wrote {out / 'table1.md'}, {out / 'table1.json'}, {out / 'table1.csv'} and {out / 'table1.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
