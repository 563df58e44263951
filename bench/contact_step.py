"""Time contact: what 1,000 active contacts add to a 15,360-tet step, and the armadillo
dropped onto the floor in real time.

    taskset -c 1 python bench/contact_step.py [--data ../shared/data/armadillo_4k.vtu] [--repeats 5]

1. The standard 15,360-tet beam (bench/README.md: 5 x 1 x 1 m, 40 x 8 x 8 cubes of 6 tets,
   E = 1e7 Pa, corotate.PCG(), dt = 0.01 s), run two ways in turns: clamped at x = 0 without
   contact (the baseline), and lying free on the floor between two walls that touch its
   sides (369 + 2 x 369 = 1,107 contact nodes, friction 0.3), settled first. Each run times
   --steps steps; the medians of --repeats runs and their ratio are printed.
2. The armadillo (the shared data's armadillo_4k.vtu, 3,717 tets, scaled by 0.1 as in the
   Table 1 study; E = 1e6 Pa, nu = 0.33), dropped from 5 cm onto the floor with friction 0.5,
   five 0.01 s steps per frame as in Table 1: ms per step, CG iterations and the real-time
   ratio (simulated over wall seconds) over 3 s, landing included.
3. ToolFeedback.query, the haptic loop's call, from Python; and contact between bodies: the
   contact guide's two soft cubes (384 tets each, a Scene) stacked off-centre on the floor,
   300 steps, with and without edge-against-edge contact in turns: ms per step and CG
   iterations; and the same pair at 12,000 tets (two-level PCG), landing and at rest.
   What detection costs where nothing touches: the clamped beam alone, the same beam and a
   1,920-tet beam 2 m apart in one Scene, and the beam alone with self-contact on.
4. Table 1's cage (studies/table1_dog.py: the armadillo's boundary tetrahedralized at about
   700 tets; needs the [mesh] extra, else skipped) dropped 5 cm onto the floor against the
   same cage hanging from its anchor, Table 1's row (a) scene, and dropped with its render
   surface's vertices as the contact points: the real-time ratio of each; then, untimed,
   how deep the render surface goes into the floor on the cage's nodes and on its own, and
   how far the hanging cage's path strays when steps keep their matrix (matrix_reuse_angle
   0.03, 0.05, 0.2 against every step assembled and solved directly).
Prints the CPU and the instruction set the core was built for.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from bench_machine import describe_machine

import corotate as cr

ARMADILLO = Path(__file__).resolve().parents[2] / "shared" / "data" / "armadillo_4k.vtu"


def beam_runs(steps: int, repeats: int) -> None:
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(40, 8, 8))
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0))
    clamped = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81))
    clamped.fix(mesh.nodes_on_plane("x", 0.0))
    lying = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81))
    for obstacle in (cr.Plane((0, 0, 0), (0, 0, 1)), cr.Plane((0, 0, 0), (0, 1, 0)), cr.Plane((0, 1, 0), (0, -1, 0))):
        lying.add_obstacle(obstacle, friction=0.3)
    lying.step(50)  # settled on the floor
    clamped.step(50)
    times: dict[str, list[float]] = {"clamped, no contact": [], "on the floor between walls": []}
    iterations: dict[str, list[float]] = {k: [] for k in times}
    for _ in range(repeats):
        for name, sim in zip(times, (clamped, lying)):
            sim.reset_stats()
            t0 = time.perf_counter()
            sim.step(steps)
            times[name].append((time.perf_counter() - t0) / steps * 1e3)
            iterations[name].append(sim.stats["iterations_per_step"])
    contacts = len(lying.contacts["nodes"])
    print(f"15,360-tet beam, {steps} steps x {repeats} runs, interleaved ({contacts} active contacts):")
    for name in times:
        print(
            f"  {name:28s} {np.median(times[name]):7.2f} ms/step  (runs {min(times[name]):.2f}-{max(times[name]):.2f}),"
            f" {np.median(iterations[name]):.1f} CG iterations"
        )
    ratio = np.median(times["on the floor between walls"]) / np.median(times["clamped, no contact"])
    print(f"  contact step / plain step: {ratio:.2f}")


def armadillo_drop(path: Path, seconds: float) -> None:
    volume = cr.read_mesh(path)
    mesh = cr.Mesh(volume.points * 0.1, volume.cells, "tetra")
    lift = 0.05 - mesh.points[:, 1].min()
    mesh = cr.Mesh(mesh.points + np.array([0.0, lift, 0.0]), mesh.cells, "tetra")
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.33, density=1000.0)), dt=0.01, gravity=(0, -9.81, 0))
    sim.add_obstacle(cr.Plane((0, 0, 0), (0, 1, 0)), friction=0.5)
    frames = round(seconds / 0.05)
    deepest = 0.0
    for _ in range(frames):
        sim.step(5)
        deepest = min(deepest, sim.positions[:, 1].min())
    s = sim.stats
    print(
        f"armadillo ({mesh.n_cells} tets) dropped 5 cm onto the floor, {seconds:.0f} s in frames of 5 steps: "
        f"{s['ms_per_step']:.3f} ms/step, {s['iterations_per_step']:.1f} CG iterations, "
        f"{s['real_time_ratio']:.0f}x real time; {len(sim.contacts['nodes'])} contacts at the end, "
        f"deepest {-deepest * 1e3:.3f} mm"
    )


def cage_drop(path: Path, repeats: int, cache: Path) -> None:
    """Table 1's cage (studies/table1_dog.py, about 700 tets) dropped 5 cm onto the floor, against
    the same cage hanging from its anchor (Table 1's row (a) scene, no contact), interleaved: the
    real-time ratio of each, FE mesh only. Needs the [mesh] extra (the cage is tetrahedralized
    once into `cache`)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository's studies
    from studies.table1_dog import ANCHOR, build_scene

    try:
        cage, render = build_scene(path, 700, cache)
    except ImportError as e:
        print(f"Table 1 cage drop skipped: {e}")
        return
    body = cr.Body(cage, cr.Material(E=1e6, nu=0.33, density=1000.0))
    skin = cr.EmbeddedSurface(body, render.points, render.cells, max_outside_distance=2.0)
    floor = cr.Plane((0, min(cage.points[:, 1].min(), render.points[:, 1].min()) - 0.05, 0), (0, 1, 0))
    runs: dict[str, list[float]] = {
        "hanging (row (a))": [],
        "dropped on the floor": [],
        f"the same, its {skin.n_vertices} render vertices touching": [],
    }
    iterations: dict[str, float] = {}
    contacts = 0
    for _ in range(repeats):
        for name in runs:
            sim = cr.Simulation(body, dt=0.01, gravity=(0, -9.81, 0))
            if name.startswith("hanging"):
                sim.fix(cage.nodes_where(lambda p: np.linalg.norm(p - ANCHOR, axis=1) < 0.04))
            else:
                if name.startswith("the same"):
                    sim.set_contact_surface(skin)
                sim.add_obstacle(floor, friction=0.5)
            t0 = time.perf_counter()
            sim.step(300)
            runs[name].append(3.0 / (time.perf_counter() - t0))
            iterations[name] = sim.stats["iterations_per_step"]
            contacts = max(contacts, len(sim.contacts["nodes"]))
    print(f"Table 1's cage ({cage.n_cells} tets), 300 steps of 0.01 s, median of {repeats} interleaved runs:")
    for name, ratios in runs.items():
        ratio = float(np.median(ratios))
        print(
            f"  {name:45s} {1e3 * 0.01 / ratio:6.3f} ms/step {ratio:6.0f}x real time, "
            f"{iterations[name]:.1f} CG iterations"
        )
    ratio = np.median(runs["hanging (row (a))"]) / np.median(runs["dropped on the floor"])
    print(f"  the drop's step / the hanging step: {ratio:.2f} ({contacts} contacts at the end)")
    kept_matrix_paths(cage, body)
    # Untimed: how deep the render surface goes into the floor, at every step and at the end.
    for name, on_skin in (("the cage's nodes", False), ("the render vertices", True)):
        sim = cr.Simulation(body, dt=0.01, gravity=(0, -9.81, 0))
        if on_skin:
            sim.set_contact_surface(skin)
        sim.add_obstacle(floor, friction=0.5)
        deepest = 0.0
        for _ in range(300):
            sim.step()
            skin.update(sim, normals="none")
            deepest = max(deepest, -float(floor.distance(skin.positions)[0].min()))
        end = -float(floor.distance(skin.positions)[0].min())
        print(
            f"  touching on {name}: the render surface {1e3 * deepest:.2f} mm into the floor at most, "
            f"{1e3 * end:.2f} mm at the end"
        )


def kept_matrix_paths(cage: cr.Mesh, body: cr.Body) -> None:
    """Untimed: how far the hanging cage's path strays when steps keep their matrix
    (matrix_reuse_angle), against the path with the matrix assembled and solved directly at
    every step: the largest node deviation over 300 steps, relative to the largest
    displacement."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from studies.table1_dog import ANCHOR

    anchor = cage.nodes_where(lambda p: np.linalg.norm(p - ANCHOR, axis=1) < 0.04)

    def path(angle: float, solver: cr.PCG | cr.Direct) -> np.ndarray:
        sim = cr.Simulation(body, dt=0.01, gravity=(0, -9.81, 0), solver=solver, matrix_reuse_angle=angle)
        sim.fix(anchor)
        steps = []
        for _ in range(300):
            sim.step()
            steps.append(sim.displacements.copy())
        return np.array(steps)

    reference = path(0.0, cr.Direct())
    largest = np.abs(reference).max()
    print("  the hanging cage's path off the one assembled at every step (largest node deviation):")
    for angle in (0.03, 0.05, 0.2):
        deviations = [np.abs(path(angle, solver) - reference).max() / largest for solver in (cr.Direct(), cr.PCG())]
        print(
            f"    matrix_reuse_angle {angle}: {100 * deviations[0]:.2f} % (direct solves), "
            f"{100 * deviations[1]:.2f} % (the default PCG)"
        )


def stacked_cubes(repeats: int) -> None:
    """The contact guide's two soft cubes stacked off-centre on the floor, 300 steps, with and
    without edge-against-edge contact, in turns: ms per step (median) and CG iterations."""
    soft = cr.Material(E=1e5, nu=0.3, density=1000.0)
    lower = cr.Body(cr.box((0.1, 0.1, 0.1), (4, 4, 4), origin=(-0.05, -0.05, 0.0)), soft)
    upper = cr.Body(cr.box((0.1, 0.1, 0.1), (4, 4, 4), origin=(-0.02, -0.04, 0.12)), soft)
    scene = cr.Scene([lower, upper])
    runs: dict[bool, list[float]] = {True: [], False: []}
    iterations: dict[bool, float] = {}
    for _ in range(repeats):
        for edges in runs:
            sim = scene.simulation(friction=0.3, gravity=(0, 0, -9.81))
            sim.contact_settings = {"edge_contact": edges}
            sim.add_obstacle(cr.Plane(), friction=0.5)
            sim.step(300)
            runs[edges].append(sim.stats["ms_per_step"])
            iterations[edges] = sim.stats["iterations_per_step"]
    print(f"two soft cubes stacked on the floor (a Scene, 2 x {lower.mesh.n_cells} tets), 300 steps:")
    for edges, times in runs.items():
        print(
            f"  edge contact {'on ' if edges else 'off'}: {np.median(times):.3f} ms/step, "
            f"{iterations[edges]:.1f} CG iterations"
        )
    # The same pair at 10 x 10 x 10 cells (12,000 tets, 7,986 unknowns: the two-level
    # preconditioner's size): the landing's first 100 steps, then 100 at rest.
    big = [
        cr.Body(cr.box((0.1, 0.1, 0.1), (10, 10, 10), origin=b.mesh.points.min(axis=0)), soft) for b in (lower, upper)
    ]
    sim = cr.Scene(big).simulation(friction=0.3, gravity=(0, 0, -9.81))
    sim.add_obstacle(cr.Plane(), friction=0.5)
    print(f"the same cubes at 2 x {big[0].mesh.n_cells} tets (two-level PCG):")
    for phase in ("landing, steps 0-100", "at rest, steps 100-200"):
        sim.reset_stats()
        sim.step(100)
        s = sim.stats
        print(f"  {phase}: {s['ms_per_step']:.1f} ms/step, {s['iterations_per_step']:.1f} CG iterations")


def detection_cost(steps: int, repeats: int) -> None:
    """The 15,360-tet beam clamped at x = 0: alone, with a 1,920-tet beam 2 m beside it in one
    Scene (contact between bodies detected, none made), and alone with self-contact on, in
    turns: ms per step (median, process time) after a first step."""
    material = cr.Material(E=1e7, nu=0.3, density=1000.0)
    beam = cr.Body(cr.beam(5, 1, 1, cells=(40, 8, 8)), material)
    beside = cr.Body(cr.box((5, 1, 1), (20, 4, 4), origin=(0, 3, 0)), material)
    scene = cr.Scene([beam, beside])

    def clamped(k: int, body: cr.Body) -> np.ndarray:
        return scene.nodes(k, body.mesh.nodes_where(lambda p: p[:, 0] < 1e-9))

    def simulation(kind: str) -> cr.Simulation:
        if kind == "two beams apart in a Scene":
            sim = scene.simulation(gravity=(0, 0, -9.81))
            sim.fix(np.concatenate([clamped(0, beam), clamped(1, beside)]))
            return sim
        sim = cr.Simulation(beam, gravity=(0, 0, -9.81))
        sim.fix(beam.mesh.nodes_where(lambda p: p[:, 0] < 1e-9))
        if kind == "self-contact on":
            sim.set_part_contact(self_contact=True)
        return sim

    runs: dict[str, list[float]] = {"alone": [], "two beams apart in a Scene": [], "self-contact on": []}
    for _ in range(repeats):
        for kind in runs:
            sim = simulation(kind)
            sim.step()
            t0 = time.process_time()
            sim.step(steps)
            runs[kind].append(1e3 * (time.process_time() - t0) / steps)
    print(f"detection where nothing touches, the {beam.mesh.n_cells}-tet beam clamped, {steps} steps x {repeats}:")
    for kind, times in runs.items():
        print(f"  {kind:28s} {np.median(times):.2f} ms/step")


def feedback_query(repeats: int) -> None:
    """Microseconds per ToolFeedback.query from Python (the haptic loop's call)."""
    mesh = cr.box((0.1, 0.1, 0.1), (8, 8, 8))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e5, nu=0.3, density=1000.0)))
    sim.fix(np.flatnonzero(mesh.points[:, 2] == 0))
    probe = cr.Sphere((0.05, 0.05, 0.12), 0.02)
    sim.add_obstacle(probe)
    feedback = cr.ToolFeedback(sim, probe)
    for step in range(1, 21):
        probe.move_to((0.05, 0.05, 0.12 - 5e-4 * step))
        sim.step()
        feedback.update()
    p = probe.position
    runs = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(10000):
            feedback.query(p)
        runs.append((time.perf_counter() - t0) / 10000 * 1e6)
    print(f"ToolFeedback.query from Python: {np.median(runs):.1f} us (median of {repeats} runs of 10,000 calls)")


def main() -> None:
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--data", default=str(ARMADILLO), help="the armadillo tet mesh (default: %(default)s)")
    p.add_argument("--steps", type=int, default=20, help="steps per timed run of the beam (default 20)")
    p.add_argument("--repeats", type=int, default=5, help="runs per beam configuration (default 5)")
    p.add_argument("--seconds", type=float, default=3.0, help="simulated seconds of the armadillo drop (default 3)")
    p.add_argument(
        "--cache",
        default=str(Path.home() / ".cache" / "corotate" / "table1"),
        help="where Table 1's cage is kept once tetrahedralized (default: %(default)s)",
    )
    args = p.parse_args()
    data = Path(args.data)
    if not data.is_file():
        p.error(f"the armadillo mesh is not at {data}: pass its path with --data (the shared data beside the clone)")
    print(describe_machine())
    feedback_query(args.repeats)
    stacked_cubes(args.repeats)
    detection_cost(args.steps, args.repeats)
    beam_runs(args.steps, args.repeats)
    armadillo_drop(data, args.seconds)
    cage_drop(data, args.repeats, Path(args.cache))


if __name__ == "__main__":
    main()
