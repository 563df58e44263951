"""Command line: ``corotate demo`` (the main job), ``corotate view`` (live, with the mouse), ``corotate scenes``
(explicit mass-spring and StVK scenes), ``corotate bench`` and ``corotate sweep`` (parameter sweeps on Dask)."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .build import describe_build
from .mesh import SOLID_ELEMENTS, VOLUME_CELL_TYPES, Mesh, read_mesh


def _demo_simulation(args: argparse.Namespace) -> tuple[Any, Any, np.ndarray, np.ndarray, int]:
    """The body of ``demo`` and ``view`` from their shared options: (mesh, simulation, fixed
    nodes, gravity, clamped axis)."""
    from . import PCG, Body, Material, Simulation, beam

    if args.mesh:
        mesh = read_mesh(args.mesh)
    else:
        mesh = beam(args.length, 1.0, 1.0, cells=(args.cells * 5, args.cells, args.cells), element=args.element)
    axis = "xyz".index(args.fix_axis)
    lo = mesh.points[:, axis].min()
    extent = np.ptp(mesh.points, axis=0).max()
    fixed = mesh.nodes_where(lambda p: p[:, axis] <= lo + args.fix_fraction * extent)
    if args.gravity is not None:
        gravity = np.asarray(args.gravity, dtype=float)
    elif args.mesh:  # a mesh file: gravity along its longest extent, so a figure stands upright
        gravity = np.zeros(3)
        gravity[int(np.argmax(np.ptp(mesh.points, axis=0)))] = -9.81
    else:
        gravity = np.array([0.0, 0.0, -9.81])
    body = Body(mesh, Material(E=args.E, nu=args.nu, density=args.density), model=args.model)
    sim = Simulation(body, dt=args.dt, solver=PCG(), gravity=gravity, rayleigh=(args.damping, 0.0))
    sim.fix(fixed)
    return mesh, sim, fixed, gravity, axis


def _demo(args: argparse.Namespace) -> int:
    from . import TimeSeriesWriter
    from .picture import render_snapshots

    mesh, sim, fixed, gravity, axis = _demo_simulation(args)
    extent = np.ptp(mesh.points, axis=0).max()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    pvd = out / "demo.pvd"
    print(
        f"corotate demo: {mesh.n_cells} {mesh.cell_type} cells, {mesh.n_nodes} nodes, {len(fixed)} fixed; "
        f"{args.model} model, dt = {args.dt} s, {args.steps_per_frame} steps per frame, {args.frames} frames, "
        f"gravity {tuple(float(g) for g in gravity)} m/s^2, damping {args.damping} 1/s"
    )
    snapshots = [(0.0, sim.positions.copy())]
    every = max(1, args.frames // 5)  # the picture: about six instants of the run
    with TimeSeriesWriter(pvd, mesh) as writer:
        writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
        for frame in range(1, args.frames + 1):
            sim.step(args.steps_per_frame)
            writer.write(sim.time, sim.positions, {"velocity": sim.velocities})
            if frame % every == 0 or frame == args.frames:
                snapshots.append((round(sim.time, 6), sim.positions.copy()))
            _progress(frame, args.frames)
    s = sim.stats
    far = mesh.points[:, axis] >= mesh.points[:, axis].max() - 1e-9 * extent
    print(
        f"  simulated {s['simulated_time']:.2f} s in {s['wall_time']:.3f} s of stepping: "
        f"real-time ratio {s['real_time_ratio']:.1f}, {s['ms_per_step']:.3f} ms per step, "
        f"{s['iterations_per_step']:.2f} CG iterations per step"
    )
    print(f"  far-end mean displacement z: {sim.displacements[far, 2].mean():+.4f} m")
    print(f"  wrote {pvd} ({args.frames + 1} frames; open it in ParaView, colour by 'displacement')")
    if args.picture:
        try:
            up = "+z"
            if np.any(gravity):  # draw the figure upright: against gravity's main axis
                k = int(np.argmax(np.abs(gravity)))
                up = ("-" if gravity[k] > 0 else "+") + "xyz"[k]
            png = render_snapshots(out / "demo.png", mesh, snapshots, title=f"corotate demo: {args.model} model", up=up)
            print(f"  wrote {png} (the surface at {len(snapshots)} instants)")
        except ImportError:
            print("  no picture: it needs matplotlib (pip install 'corotate-fem[plot]')")
    return 0


def _progress(frame: int, frames: int) -> None:
    """A one-line progress bar on a terminal (nothing when the output is redirected)."""
    if not sys.stdout.isatty():
        return
    width = 30
    done = width * frame // frames
    end = "\n" if frame == frames else ""
    print(f"\r  [{'#' * done}{'.' * (width - done)}] frame {frame}/{frames}", end=end, flush=True)


def _view(args: argparse.Namespace) -> int:
    from .view import InteractiveScene, Window

    mesh, sim, fixed, gravity, _ = _demo_simulation(args)
    probe_radius = None
    if args.contact:
        # Dropped on a floor instead of clamped, and pushed by a probe that follows the mouse.
        from .obstacles import Plane

        sim.free()
        fixed = np.zeros(0, dtype=np.int64)
        up = -gravity / np.linalg.norm(gravity) if np.any(gravity) else np.array([0.0, 0.0, 1.0])
        extent = float(np.ptp(mesh.points, axis=0).max())
        lowest = float((mesh.points @ up).min())
        sim.add_obstacle(Plane(point=(lowest - 0.1 * extent) * up, normal=up), friction=0.5)
        probe_radius = 0.1 * extent
    surface = None
    if args.surface:
        from .embedding import EmbeddedSurface

        surface = EmbeddedSurface.from_file(sim.body, args.surface)
    scene = InteractiveScene(
        sim, surface=surface, max_steps=args.steps_per_frame, gravity=gravity, probe_radius=probe_radius
    )
    print(
        f"corotate view: {mesh.n_cells} {mesh.cell_type} cells, {mesh.n_nodes} nodes, {len(fixed)} fixed"
        + (f", showing {args.surface} ({len(scene.triangles)} triangles)" if surface is not None else "")
        + f"; grab stiffness {scene.grab_stiffness:.3g} N/m"
        + ("; dropped on a floor, Ctrl + mouse moves the probe" if args.contact else "")
    )
    window = Window(scene, backend=args.backend)
    if args.frames is None:
        window.show()
    else:
        window.run_frames(args.frames)
    if args.screenshot:
        window.screenshot(args.screenshot)
        print(f"  wrote {args.screenshot}")
    print(f"  {scene.status()}")
    return 0


def _scenes(args: argparse.Namespace) -> int:
    from . import scenes

    names = ["cloth", "cube", "sheet"] if args.scene == "all" else [args.scene]
    if "cloth" in names:
        scenes.hanging_cloth(args.out, n=args.cloth_size, frames=args.frames, integrator=args.integrator)
    if "cube" in names:
        scenes.dropped_cube(args.out, cells=args.cube_cells, frames=args.frames, integrator=args.integrator)
    if "sheet" in names:
        scenes.stvk_sheet(args.out, frames=args.frames)
    print(
        "  open the .pvd files in ParaView (the cloth as quads, the cube as hexahedra, the sheet as triangles, "
        "colour by 'displacement')"
    )
    return 0


def _bench(args: argparse.Namespace) -> int:
    exe = Path(__file__).parent / "bin" / ("corotate_bench.exe" if os.name == "nt" else "corotate_bench")
    if not exe.exists():
        print(f"corotate bench: the benchmark executable is not installed at {exe}", file=sys.stderr)
        return 2
    bench_args = list(args.bench_args)
    with tempfile.TemporaryDirectory() as folder:
        # The benchmark reads no mesh format itself: --mesh FILE is read here, by read_mesh
        # (any format it reads, checked), and handed over as text under the file's own stem.
        if "--mesh" in bench_args[:-1]:
            i = bench_args.index("--mesh") + 1
            source = Path(bench_args[i])
            try:
                mesh = read_mesh(source)
            except (OSError, ValueError) as e:
                print(f"corotate bench: {e}", file=sys.stderr)
                return 2
            bench_args[i] = str(Path(folder) / source.name.split(".")[0])
            _write_bench_mesh(mesh, bench_args[i])
        return subprocess.call([str(exe), *bench_args])


def _write_bench_mesh(mesh: Mesh, path: str) -> None:
    """The mesh in the benchmark's text form: "n m k", n rows x y z, m rows of k node
    indices, the cell type (bench/beam_scenario.hpp, read_mesh)."""
    with open(path, "w") as out:
        out.write(f"{mesh.n_nodes} {mesh.n_cells} {mesh.cells.shape[1]}\n")
        np.savetxt(out, mesh.points, fmt="%.17g")
        np.savetxt(out, mesh.cells, fmt="%d")
        out.write(f"{mesh.cell_type}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="corotate", description="Fast co-rotational FEM simulation of elastic solids."
    )
    parser.add_argument("--version", action="version", version=describe_build())
    sub = parser.add_subparsers(dest="command", required=True)

    demo = sub.add_parser(
        "demo",
        help="run the default scene and write a ParaView time series",
        description="A soft cantilever (5 x 1 x 1 m, clamped at x = 0) falls under gravity: co-rotational FEM, "
        "implicit steps of dt = 0.01 s, five steps per frame as in the paper's Table 1. Writes "
        "OUT/demo.pvd (+ one .vtu per frame, with displacement and velocity), a picture OUT/demo.png "
        "(with matplotlib) and prints the real-time ratio. With --mesh, the same on any mesh file of "
        f"{'/'.join(VOLUME_CELL_TYPES)} cells.",
    )
    demo.add_argument("--out", default="corotate-demo", help="output folder (default: corotate-demo)")
    demo.add_argument("--frames", type=int, default=60, help="frames to write (default 60)")
    demo.add_argument(
        "--no-picture",
        dest="picture",
        action="store_false",
        help="do not write OUT/demo.png (the surface at six instants; written when matplotlib is installed)",
    )
    _add_body_arguments(demo)
    demo.set_defaults(func=_demo)

    view = sub.add_parser(
        "view",
        help="watch the demo body live in a window and drag it with the mouse (needs the extra [view])",
        description="The demo's body (or --mesh) simulated live in a polyscope window, paced to the wall clock "
        "(at most --steps-per-frame steps per frame). Shift + left drag grabs the node nearest to the point "
        "under the cursor and pulls it through a stiff implicit spring (Simulation.attach); the panel pauses, "
        "resets, switches gravity and shows the real-time ratio. --surface shows a render surface embedded in "
        "the body instead of its boundary. Needs polyscope: pip install 'corotate-fem[view]'.",
    )
    view.add_argument("--surface", help="a triangle surface file (.obj, .stl, .ply, ...) to embed in the body and show")
    view.add_argument(
        "--frames", type=int, default=None, help="run this many frames and return instead of waiting for the window"
    )
    view.add_argument("--screenshot", help="write a PNG of the last frame to this path")
    view.add_argument(
        "--contact",
        action="store_true",
        help="drop the body (not clamped) on a floor and push it with a probe sphere that follows the mouse "
        "while Ctrl is held; the panel shows the force on the probe",
    )
    view.add_argument(
        "--backend",
        default="auto",
        choices=["auto", "openGL3_glfw", "openGL3_egl", "openGL_mock"],
        help="polyscope backend (default auto; openGL_mock draws nothing, for tests)",
    )
    _add_body_arguments(view)
    view.set_defaults(func=_view)
    return _add_other_commands(parser, sub)


def _add_body_arguments(demo: argparse.ArgumentParser) -> None:
    """The body and stepping options that ``demo`` and ``view`` share."""
    demo.add_argument("--steps-per-frame", type=int, default=5, help="time steps per frame (default 5)")
    demo.add_argument("--dt", type=float, default=0.01, help="time step in seconds (default 0.01)")
    demo.add_argument("--mesh", help="mesh file (.vtu, .msh, TetGen .node/.ele, ...) instead of the beam")
    demo.add_argument(
        "--cells", type=int, default=4, help="beam cross-section cells (beam: 5c x c x c cubes; default 4)"
    )
    demo.add_argument("--length", type=float, default=5.0, help="beam length in m (default 5)")
    demo.add_argument("--element", default="tet4", choices=SOLID_ELEMENTS, help="beam element (default tet4)")
    demo.add_argument("--model", default="corotational", choices=["corotational", "linear"], help="force model")
    demo.add_argument(
        "--gravity",
        type=float,
        nargs=3,
        metavar=("GX", "GY", "GZ"),
        help="gravity in m/s^2 (default: 0 0 -9.81 for the beam; for --mesh, -9.81 along the mesh's longest axis)",
    )
    demo.add_argument(
        "--damping",
        type=float,
        default=1.0,
        help="mass-proportional damping alpha in 1/s (Rayleigh alpha; default 1: the swing dies out "
        "over a few seconds; 0 swings undamped)",
    )
    demo.add_argument("--E", type=float, default=1e6, help="Young's modulus in Pa (default 1e6: soft)")
    demo.add_argument("--nu", type=float, default=0.3, help="Poisson ratio (default 0.3)")
    demo.add_argument("--density", type=float, default=1000.0, help="density in kg/m^3 (default 1000)")
    demo.add_argument(
        "--fix-axis", default="x", choices=["x", "y", "z"], help="clamp the nodes at the minimum of this axis"
    )
    demo.add_argument(
        "--fix-fraction",
        type=float,
        default=0.0,
        help="clamp nodes within this fraction of the mesh size of that minimum (default 0)",
    )


def _add_other_commands(parser: argparse.ArgumentParser, sub: Any) -> argparse.ArgumentParser:

    scenes = sub.add_parser(
        "scenes",
        help="scenes: a cloth hanging from two corners, a soft cube dropped on a base, a StVK sheet swinging",
        description="Bodies stepped explicitly (frames of 1/60 s, sub-stepped at the critical time step): a "
        "mass-spring cloth pinned at two corners falls and swings; a soft mass-spring cube lattice "
        "lands on a pinned base; the explainer's 2D St. Venant-Kirchhoff sheet of triangles swings "
        "from two corners (symplectic Euler). Writes OUT/cloth.pvd, OUT/cube.pvd and OUT/sheet.pvd (+ .vtu frames) "
        "and a PNG of each (PNG needs matplotlib: pip install matplotlib, or the extra 'corotate-fem[plot]'). "
        "The paper's figures (the thin plate of Fig. 5 among them) are reproduced by the scripts in the "
        "repository's studies/ folder.",
    )
    scenes.add_argument(
        "scene",
        nargs="?",
        default="all",
        choices=["all", "cloth", "cube", "sheet"],
        help="which scene (default all)",
    )
    scenes.add_argument("--out", default="corotate-scenes", help="output folder (default: corotate-scenes)")
    scenes.add_argument("--frames", type=int, default=240, help="frames of 1/60 s (default 240)")
    scenes.add_argument("--cloth-size", type=int, default=32, help="cloth particles per side (default 32)")
    scenes.add_argument("--cube-cells", type=int, default=6, help="cube lattice cells per side (default 6)")
    scenes.add_argument(
        "--integrator", default="verlet", choices=["verlet", "symplectic_euler"], help="explicit integrator"
    )
    scenes.set_defaults(func=_scenes)

    bench = sub.add_parser(
        "bench",
        help="run the C++ benchmark executable (pass its options after --)",
        description="Runs the installed corotate_bench; e.g. 'corotate bench -- --sizes 1,2,4'. "
        "'corotate bench -- --help' lists its options.",
    )
    bench.add_argument("bench_args", nargs=argparse.REMAINDER, help="options for corotate_bench")
    bench.set_defaults(func=_bench)

    from .sweep.cli import add_sweep_command

    add_sweep_command(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``corotate`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "bench" and args.bench_args[:1] == ["--"]:
        args.bench_args = args.bench_args[1:]
    try:
        return args.func(args)
    except (ValueError, RuntimeError, FileNotFoundError, ImportError) as err:  # ImportError: a missing extra
        print(f"corotate {args.command}: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
