"""A flexible pendulum (issue 25): a link on a revolute joint, released horizontal under
gravity, run for 2 s as a full co-rotational body, as corotate's floating-frame body
(FloatingBody) and as Exudyn's (ObjectFFRFreducedOrder) built from corotate's Craig-Bampton
basis. How close are their tip paths, and what decides it: the basis size, the hinge's model,
or what a floating frame with linear modes leaves out?

The link: 1 x 0.05 x 0.05 m, density 7850 kg/m^3, E = 3e8 Pa, nu = 0.3 (its tip bends about 3 %
of its length against the frame of its root), Hex20 10 x 2 x 2 cells, its origin on the hinge
axis (x = 0, z = 0, along y); gravity -z.

* Full co-rotational (corotate): the five nodes on the hinge axis fixed, the rest free to turn
  about it; backward Euler with Newton (Direct solver) at dt and dt/2. Backward Euler is first
  order and damps, so the reference is the Richardson extrapolation 2 x(dt/2) - x(dt).
* corotate's FloatingBody on a revolute joint, n normal modes of the root-face basis, step
  min(dt, 1 ms), stiffened by its inertial loads and gravity, or linear (as Exudyn's body is).
* Exudyn, with corotate.modal.to_exudyn and generalized-alpha without numerical damping
  (spectral radius 1, step min(dt, 1 ms)), n normal modes of one of two Craig-Bampton bases:
  "root face": the root face fixed in the basis (it is the floating frame), a revolute joint
  from the ground to a rigid marker on the root nodes (the face stays plane);
  "hinge axis": the hinge-axis nodes and one DOF off the axis fixed in the basis (the frame
  turns with that DOF), a revolute joint at the frame's origin: the full run's hinge exactly.

The error of a tip path is the largest distance between tip positions (mean of the tip face's
nodes) at equal times, over the path's radius L (and its RMS over time). The energy change of
a linear floating-frame run is that of the exact energy of its kinematics x = p + R (X + Psi q)
(ffrf_energy, one formula for both codes' states) over m g L / 2.

What it shows (defaults): corotate's stiffened floating frame is within 0.15 % (8 modes) and
0.23 % (4 modes) of L of the full co-rotational tip: the stiffening is what the linear frame
misses. With 16 modes the stiffened step goes unstable at 0.7 s (its path stops there): held at
its root face, the basis carries nearly all of the link's rotation (the frame keeps 0.02 % of
its rotational inertia about the hinge, against 0.15 % with 8 modes), and the stiffening, which
acts on the modes alone, feeds the frame's fast motion that this leaves.
The linear runs lag by 0.85-0.92 % of L (RMS 0.37 %), Exudyn's and corotate's alike: the two
codes run the same model, and their tip paths stay within 1e-6 L of each other over the 2 s
(4, 8 and 16 modes), both keeping the exact energy (Exudyn to 1.3e-6 of m g L / 2, corotate to
4e-8). The basis is converged at 8 modes; the exact hinge (the hinge-axis basis) changes the
error by 0.15 %. Gravity reaches Exudyn's body as the consistent nodal loads (to_exudyn): with
Exudyn's own mass-proportional load instead, its run lost up to 0.8 % of the energy at the
bottom of the swing and lay 1.8 % of L from corotate's. A stiffer link narrows every gap (--E 1e9,
--E 3e9). The extrapolated reference is good to ~0.14 % of L (the extrapolations from 1 and
0.5 ms and from 0.5 and 0.25 ms differ by that); the 0.25 ms backward-Euler run alone is 1.6 %
off by 2 s (it damps). Exudyn's step (1 ms) is converged (0.5 ms: 4e-5 L).

    python -m studies.flexible_pendulum --out flexible-pendulum   # tip_paths.csv, errors.csv, flexible_pendulum.png
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np

import corotate as cr
from corotate.modal import FloatingBody, craig_bampton, to_exudyn

from ._common import output_folder, parser, pyplot, save_figure, write_csv

L, B, H = 1.0, 0.05, 0.05
MATERIAL = cr.Material(E=3e8, nu=0.3, density=7850.0)
CELLS = (10, 2, 2)
GRAVITY = (0.0, 0.0, -9.81)
FRAMES = ("root face", "hinge axis")


def link() -> tuple[cr.Mesh, np.ndarray, np.ndarray, np.ndarray]:
    """The link's mesh (its origin on the hinge axis, the y axis), its hinge-axis nodes, its
    root face nodes and its tip face nodes."""
    mesh = cr.box((L, B, H), cells=CELLS, element="hex20", origin=(0.0, -B / 2, -H / 2))
    p = mesh.points
    axis = np.flatnonzero(np.isclose(p[:, 0], 0.0) & np.isclose(p[:, 2], 0.0))
    return mesh, axis, mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", L)


def full_tip_path(dt: float, duration: float, every: int = 1, material: cr.Material = MATERIAL) -> np.ndarray:
    """(k, 4) rows t, tip x, y, z of the full co-rotational link, every `every` steps of dt."""
    mesh, axis, _root, tip = link()
    sim = cr.Simulation(
        cr.Body(mesh, material, model="corotational"), dt=dt, solver=cr.Direct(), gravity=GRAVITY, integrator="newton"
    )
    sim.fix(axis)
    steps = round(duration / dt)
    rows = [(0.0, *sim.positions[tip].mean(axis=0))]
    for k in range(1, steps + 1):
        sim.step()
        if k % every == 0:
            rows.append((k * dt, *sim.positions[tip].mean(axis=0)))
    return np.array(rows)


def ffrf_energy(body: cr.Body, basis, state: dict[str, np.ndarray]) -> np.ndarray:
    """The floating-frame body's energy [J] (kinetic, elastic and gravitational, exact for its
    kinematics x = p + R (X + Psi q)) at each row of a recorded state: position p, velocity v,
    rotation R (9,), angular velocity in the frame w, modal coordinates q and their rates qd.
    The same formula for any code's state: what an undamped run must keep."""
    X = body.mesh.points
    V = basis.vectors
    M = body.mass_matrix(lumped=False).tocsr()
    K_r = V.T @ (body.stiffness_matrix() @ V)
    g = np.tile(GRAVITY, len(X))
    out = []
    for p, v, R, w, q, qd in zip(*(state[k] for k in ("p", "v", "R", "w", "q", "qd")), strict=True):
        R = R.reshape(3, 3)
        local = X + (V @ q).reshape(-1, 3)
        xd = (v + (np.cross(w, local) + (V @ qd).reshape(-1, 3)) @ R.T).ravel()
        x = (p + local @ R.T).ravel()
        out.append(0.5 * xd @ (M @ xd) + 0.5 * q @ K_r @ q - x @ (M @ g))
    return np.array(out)


def exudyn_tip_path(
    n_modes: int, times: np.ndarray, step: float, frame: str = "root face", material: cr.Material = MATERIAL
) -> tuple[np.ndarray, int, np.ndarray]:
    """(len(times), 3) tip positions of the Exudyn run with n_modes normal modes of the basis
    whose frame is `frame` (one of FRAMES) at the given times (interpolated between its sensor
    samples), the basis size, and the body's energy (ffrf_energy) at its sensor samples."""
    import exudyn as exu
    from exudyn.itemInterface import (
        GenericJoint,
        MarkerBodyRigid,
        MarkerNodeRigid,
        ObjectGround,
        SensorMarker,
        SensorNode,
    )

    mesh, axis, root, tip = link()
    body = cr.Body(mesh, material, model="linear")
    if frame == "root face":
        basis = craig_bampton(body, root, n_modes=n_modes)
    else:  # the axis nodes held, and the x DOF of a root corner so that the frame turns with it
        corner = mesh.nearest_node((0.0, -B / 2, H / 2))
        basis = craig_bampton(body, axis, n_modes=n_modes, fixed_dofs=[3 * corner])
    mbs = exu.SystemContainer().AddSystem()
    flexible = to_exudyn(mbs, body, basis, gravity=GRAVITY)
    ground = mbs.AddObject(ObjectGround())
    on_axis = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0]))
    # The root face's centroid and the frame's origin are on the axis.
    link_marker = (
        flexible.rigid_marker(root)
        if frame == "root face"
        else mbs.AddMarker(MarkerNodeRigid(nodeNumber=flexible.rigid_node))
    )
    free_about_y = [1, 1, 1, 1, 0, 1]
    mbs.AddObject(GenericJoint(markerNumbers=[on_axis, link_marker], constrainedAxes=free_about_y))
    sensor = mbs.AddSensor(
        SensorMarker(
            markerNumber=flexible.position_marker(tip),
            outputVariableType=exu.OutputVariableType.Position,
            storeInternal=True,
        )
    )
    kinds = exu.OutputVariableType
    state_sensors = {
        key: mbs.AddSensor(SensorNode(nodeNumber=node, outputVariableType=kind, storeInternal=True))
        for key, node, kind in (
            ("p", flexible.rigid_node, kinds.Position),
            ("v", flexible.rigid_node, kinds.Velocity),
            ("R", flexible.rigid_node, kinds.RotationMatrix),
            ("w", flexible.rigid_node, kinds.AngularVelocityLocal),
            ("q", flexible.modal_node, kinds.Coordinates),
            ("qd", flexible.modal_node, kinds.Coordinates_t),
        )
    }
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = step
    settings.timeIntegration.verboseMode = 0
    settings.timeIntegration.endTime = float(times[-1])
    settings.timeIntegration.numberOfSteps = round(times[-1] / step)
    settings.timeIntegration.generalizedAlpha.spectralRadius = 1.0  # no numerical damping
    mbs.SolveDynamic(settings)
    data = mbs.GetSensorStoredData(sensor)
    state = {key: mbs.GetSensorStoredData(number)[:, 1:] for key, number in state_sensors.items()}
    path = np.column_stack([np.interp(times, data[:, 0], data[:, k]) for k in (1, 2, 3)])
    return path, basis.size, ffrf_energy(body, basis, state)


def ffrf_tip_path(
    n_modes: int, times: np.ndarray, step: float, stiffening: bool, material: cr.Material = MATERIAL
) -> tuple[np.ndarray, int, np.ndarray]:
    """(len(times), 3) tip positions of corotate's floating-frame body (FloatingBody) on a
    revolute joint about the hinge axis, n_modes normal modes of the root-face basis (Exudyn's
    "root face" body), with or without the geometric stiffening of the inertial loads, stepped
    at `step` and sampled at the given times; the basis size; its energy after every step
    (ffrf_energy, the formula the Exudyn runs are judged by)."""
    mesh, _axis, root, tip = link()
    body = cr.Body(mesh, material, model="linear")
    basis = craig_bampton(body, root, n_modes=n_modes)
    fb = FloatingBody(
        body, basis, support="revolute", axis=(0.0, 1.0, 0.0), stiffening=stiffening, dt=step, gravity=GRAVITY
    )
    t, path = [0.0], [fb.positions(tip).mean(axis=0)]
    state: dict[str, list[np.ndarray]] = {key: [] for key in ("p", "v", "R", "w", "q", "qd")}

    def record() -> None:
        R = fb.rotation
        for key, value in zip(
            state, (fb.position, fb.velocity, R.ravel(), R.T @ fb.angular_velocity, fb.q, fb.modal_velocities)
        ):
            state[key].append(value)

    record()
    for _ in range(round(times[-1] / step)):
        try:
            fb.step()
        except RuntimeError as e:  # the path stops there (NaN after it); see the docstring
            print(f"corotate FFRF, {n_modes} modes, stiffening {stiffening}: stopped at t = {fb.time:.3f} s: {e}")
            break
        t.append(fb.time)
        path.append(fb.positions(tip).mean(axis=0))
        record()
    path_array = np.array(path)
    out = np.column_stack([np.interp(times, t, path_array[:, k]) for k in range(3)])
    out[times > t[-1] + 1e-12] = np.nan
    return out, basis.size, ffrf_energy(body, basis, {key: np.array(rows) for key, rows in state.items()})


def frame_inertia_share(body: cr.Body, basis) -> float:
    """The share of the body's rotational inertia about the hinge axis (y through the origin)
    that the floating frame keeps when the modes take all of that rotation they can represent:
    (I - c^T M_r^-1 c) / I, c the modes' coupling with the rotation."""
    M = body.mass_matrix(lumped=False)
    rotation = np.cross([0.0, 1.0, 0.0], body.mesh.points).ravel()
    Mrot = M @ rotation
    inertia = rotation @ Mrot
    coupling = basis.vectors.T @ Mrot
    reduced = basis.vectors.T @ (M @ basis.vectors)
    return float((inertia - coupling @ np.linalg.solve(reduced, coupling)) / inertia)


def path_error(path: np.ndarray, reference: np.ndarray) -> tuple[float, float, int]:
    """Largest and RMS distance between two (k, 3) tip paths over L, and where the largest is."""
    d = np.linalg.norm(path - reference, axis=1) / L
    if np.isnan(d).any():  # a run that stopped: its error is undefined
        return float("nan"), float("nan"), int(np.argmax(np.isnan(d)))
    return float(d.max()), float(np.sqrt(np.mean(d**2))), int(d.argmax())


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "flexible-pendulum")
    p.add_argument("--dt", type=float, default=5e-4, help="the full runs' coarser step [s] (default 5e-4; also dt/2)")
    p.add_argument("--duration", type=float, default=2.0, help="simulated time [s] (default 2)")
    p.add_argument(
        "--modes", type=int, nargs="+", default=[4, 8, 16], help="normal modes of the Exudyn bases (default 4 8 16)"
    )
    p.add_argument(
        "--E", type=float, default=MATERIAL.E, help=f"the link's Young's modulus [Pa] (default {MATERIAL.E:g})"
    )
    args = p.parse_args(argv)
    if not (args.E > 0):
        p.error("--E must be > 0")
    material = cr.Material(E=args.E, nu=MATERIAL.nu, density=MATERIAL.density)
    if not (args.dt > 0 and args.duration >= 10 * args.dt):
        p.error("--dt must be > 0 and --duration at least 10 steps")
    try:
        import exudyn  # noqa: F401
    except ImportError:
        p.error("this study needs exudyn: pip install 'corotate-fem[mbs]'")
    out = output_folder(args.out)

    t0 = time.perf_counter()
    coarse = full_tip_path(args.dt, args.duration, material=material)
    fine = full_tip_path(args.dt / 2, args.duration, every=2, material=material)
    print(f"full co-rotational runs (dt {args.dt:g} and {args.dt / 2:g} s): {time.perf_counter() - t0:.0f} s")
    times = coarse[:, 0]
    reference = 2 * fine[:, 1:] - coarse[:, 1:]  # Richardson: backward Euler's O(dt) error cancels
    mesh, axis, _root, _tip = link()
    runs = {f"full co-rotational, dt = {args.dt / 2:g} s": (fine[:, 1:], 3 * (mesh.n_nodes - axis.size))}
    energies: dict[str, np.ndarray] = {}
    t0 = time.perf_counter()
    for frame in FRAMES:
        for n in args.modes:
            path, size, energy = exudyn_tip_path(n, times, min(args.dt, 1e-3), frame, material)
            runs[f"Exudyn FFRF, {frame}, {n} modes"] = (path, 6 + size)  # the frame's six and the modal coordinates
            energies[f"Exudyn FFRF, {frame}, {n} modes"] = energy
    print(f"Exudyn runs: {time.perf_counter() - t0:.0f} s")
    t0 = time.perf_counter()
    for stiffening in (True, False):
        for n in args.modes:
            path, size, energy = ffrf_tip_path(n, times, min(args.dt, 1e-3), stiffening, material)
            kind = "stiffened" if stiffening else "linear"
            runs[f"corotate FFRF, {kind}, {n} modes"] = (path, 6 + size)
            if not stiffening:  # (a stiffened body's energy has the stiffening's share besides)
                energies[f"corotate FFRF, {kind}, {n} modes"] = energy
    # Held at its root face, the basis can carry a rotation about the hinge itself: what is left
    # to the frame shrinks with the modes (the stiffened step's trouble with many of them).
    body = cr.Body(link()[0], material, model="linear")
    for n in args.modes:
        share = frame_inertia_share(body, craig_bampton(body, link()[2], n_modes=n))
        print(f"{n} modes: the frame keeps {100 * share:.3g} % of the link's rotational inertia about the hinge")
    print(f"corotate FFRF runs: {time.perf_counter() - t0:.0f} s")

    rows = []
    mass = MATERIAL.density * L * B * H
    print("run | unknowns | max tip error / L | RMS / L | at t [s] | gap to corotate's linear FFRF / L | energy change")
    for name, (path, size) in runs.items():
        worst, rms, k = path_error(path, reference)
        # Exudyn's body and corotate's linear one are the same model (linear modes on a floating
        # frame, the root face's basis): how far apart their runs are is the implementations' gap.
        twin = f"corotate FFRF, linear, {name.rsplit(', ', 1)[-1]}"
        gap = path_error(path, runs[twin][0])[0] if "root face" in name else float("nan")
        # An undamped run keeps its energy: its largest change over m g L / 2 (the energy the
        # fall turns into motion). For the linear floating-frame runs only (see ffrf_energy).
        e = energies.get(name)
        drift = (
            float(np.abs(e - e[0]).max() / (mass * np.linalg.norm(GRAVITY) * L / 2)) if e is not None else float("nan")
        )
        rows.append((name, size, worst, rms, float(times[k]), gap, drift))
        print(f"{name} | {size} | {worst:.4f} | {rms:.4f} | {times[k]:.3f} | {gap:.4f} | {drift:.1e}")
    header = [
        "run",
        "unknowns",
        "max_error_over_L",
        "rms_error_over_L",
        "t_max_s",
        "max_gap_to_corotate_ffrf_over_L",
        "max_energy_change_over_mgL2",
    ]
    write_csv(out / "errors.csv", header, rows)
    header = ["t_s", "reference_x_m", "reference_z_m"]
    columns = [times, reference[:, 0], reference[:, 2]]
    for k, (path, _size) in enumerate(runs.values()):
        header += [f"run{k}_x_m", f"run{k}_z_m"]
        columns += [path[:, 0], path[:, 2]]
    write_csv(out / "tip_paths.csv", header, np.column_stack(columns).tolist())

    plt = pyplot()
    fig, (ax, ax_err) = plt.subplots(1, 2, figsize=(11, 4.8))
    # The paths differ by centimetres on a metre's arc: an inset magnifies where they differ most.
    worst = max(rows[1:], key=lambda row: row[2] if np.isfinite(row[2]) else -1.0) if len(rows) > 1 else rows[0]
    k = int(np.searchsorted(times, worst[4]))
    zoom = ax.inset_axes([0.3, 0.42, 0.4, 0.45])
    most = f"{8 if 8 in args.modes else max(args.modes)} modes"  # the converged basis where it was run
    for target in (ax, zoom):
        target.plot(reference[:, 0], reference[:, 2], "k-", lw=3, alpha=0.3, label="full co-rotational (extrapolated)")
    zoom.plot(reference[k, 0], reference[k, 2], "ko", ms=5, alpha=0.5)
    for name, (path, _size) in runs.items():
        if name.startswith("full") or name.endswith(most):  # the paths of the others lie on these
            (line,) = ax.plot(path[:, 0], path[:, 2], "-", lw=1, label=name)
            zoom.plot(path[:, 0], path[:, 2], "-", lw=1, color=line.get_color())
            zoom.plot(path[k, 0], path[k, 2], "o", ms=4, color=line.get_color())  # where each tip is at that time
            ax_err.semilogy(times[1:], np.linalg.norm(path - reference, axis=1)[1:] / L, lw=1, label=name)
    half = 0.04 * L
    zoom.set_xlim(reference[k, 0] - half, reference[k, 0] + half)
    zoom.set_ylim(reference[k, 2] - half, reference[k, 2] + half)
    zoom.set_aspect("equal")
    zoom.set_title(f"the tips at t = {times[k]:.2f} s", fontsize=8)
    zoom.tick_params(labelsize=6)
    ax.indicate_inset_zoom(zoom, edgecolor="0.4")
    ax.set_xlabel("tip x [m]")
    ax.set_ylabel("tip z [m]")
    ax.set_aspect("equal")
    ax.set_ylim(-1.45 * L, 0.1 * L)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower center", fontsize=7, ncol=2)
    ax.set_title("Tip path of the flexible pendulum")
    ax_err.set_xlabel("t [s]")
    ax_err.set_ylabel("|tip - reference| / L")
    ax_err.grid(alpha=0.3, which="both")
    ax_err.legend(loc="lower right", fontsize=7)
    ax_err.set_title("Distance from the extrapolated full co-rotational tip")
    png = save_figure(fig, out / "flexible_pendulum.png")
    print(f"wrote {out / 'tip_paths.csv'}, {out / 'errors.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
