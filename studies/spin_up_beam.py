"""The spin-up beam (Kane, Ryan & Banerjee 1987; issue 25): a 10 m cantilever whose hub is
spun up from rest to Omega = 6 rad/s over T = 15 s and then turns at that rate. Its tip's
in-plane deflection in the rotating frame, from three models run by this library:

* full: the 3D beam with the hub's rotation prescribed on its root face (every node free
  otherwise), StVK or co-rotational Hex20, backward Euler with Newton at dt and dt/2 and the
  Richardson extrapolation 2 x(dt/2) - x(dt) (backward Euler is first order and damps);
* FFRF, stiffened: corotate.modal.FloatingBody on the driven hub with the geometric stiffness
  of the inertial loads (the paper's §3.1 with the twelve load cases of the frame's motion);
* FFRF, linear: the same body without it, as a linear floating-frame code has it.

The beam: L = 10 m, A = 4e-4 m^2, I = 2e-7 m^4, E = 7e10 Pa, rho = 3000 kg/m^3, no hub radius.
Its mesh is a square section of side sqrt(12 I / A) with E and rho scaled by A / side^2, so EA,
EI and rho A are the beam's; nu = 0 (a beam's theory). The hub turns about z at
    omega(t) = (Omega / T) (t - (T / (2 pi)) sin(2 pi t / T))  for t < T,  Omega after.

What it shows (defaults: 20 x 1 x 1 Hex20 cells, 8 modes, full runs at 2 and 1 ms): the linear
FFRF body diverges once the hub turns faster than the beam's first frequency (3.8 rad/s), as
the literature reports: the inertial softening of the rotating frame is not balanced by the
centrifugal tension. The stiffened FFRF body stays bounded and follows the full 3D beam: its
deflection is within 5 % of the full run's peak over 0-20 s. StVK and co-rotational full runs
agree with each other to a fraction of a percent of the peak.

    python -m studies.spin_up_beam --out spin-up     # deflection.csv, summary.csv, spin_up_beam.png
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

import corotate as cr
from corotate.modal import FloatingBody, craig_bampton

from ._common import output_folder, parser, pyplot, save_figure, write_csv

LENGTH, AREA, INERTIA = 10.0, 4e-4, 2e-7
YOUNG, DENSITY = 7e10, 3000.0
OMEGA, RAMP, DURATION = 6.0, 15.0, 20.0
SIDE = float(np.sqrt(12 * INERTIA / AREA))
#: A square section of side SIDE has SIDE^2 / AREA times the area: scaling E and rho by that
#: keeps EA, rho A and (since I = SIDE^4 / 12 = INERTIA * that) EI the beam's.
SCALE = SIDE * SIDE / AREA
#: A linear FFRF run is stopped once its tip leaves the beam's length (it has diverged).
DIVERGED = LENGTH


def hub_angle(t: float) -> float:
    """The hub's angle [rad] at time t: the integral of omega(t)."""
    if t < RAMP:
        return OMEGA / RAMP * (t * t / 2 + (RAMP / (2 * np.pi)) ** 2 * (np.cos(2 * np.pi * t / RAMP) - 1))
    return OMEGA * RAMP / 2 + OMEGA * (t - RAMP)


def hub_rate(t: float) -> float:
    """The hub's angular velocity omega(t) [rad/s]."""
    if t < RAMP:
        return OMEGA / RAMP * (t - RAMP / (2 * np.pi) * np.sin(2 * np.pi * t / RAMP))
    return OMEGA


def rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def beam(cells: int, model: str = "stvk") -> tuple[cr.Body, np.ndarray, np.ndarray]:
    """The beam along x (its root face at x = 0, centred on the z axis), its root face nodes and
    its tip face nodes."""
    mesh = cr.box((LENGTH, SIDE, SIDE), cells=(cells, 1, 1), element="hex20", origin=(0.0, -SIDE / 2, -SIDE / 2))
    material = cr.Material(E=YOUNG / SCALE, nu=0.0, density=DENSITY / SCALE)
    return cr.Body(mesh, material, model=model), mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", LENGTH)


def full_deflection(cells: int, dt: float, duration: float, model: str, every: int = 1) -> np.ndarray:
    """(k, 2) rows t, tip deflection [m] in the rotating frame (its y) of the full 3D beam with
    the root face turned with the hub, every `every` steps of dt."""
    body, root, tip = beam(cells, model)
    sim = cr.Simulation(body, dt=dt, solver=cr.Direct(), integrator="newton")
    sim.fix(root)
    rest_root = body.mesh.points[root]
    rest_tip_y = body.mesh.points[tip].mean(axis=0)[1]
    rows = [(0.0, 0.0)]
    steps = round(duration / dt)
    for k in range(1, steps + 1):
        # Fixed nodes keep their velocity through a step and move by dt times it: this
        # velocity lands them on the hub's rotation at the end of the step.
        target = rest_root @ rotation_z(hub_angle(k * dt)).T
        sim.velocities[root] = (target - sim.positions[root]) / dt
        sim.step()
        sim.positions[root] = target  # the round-off of x + dt v, not left to accumulate
        if k % every == 0:
            tip_now = sim.positions[tip].mean(axis=0) @ rotation_z(hub_angle(k * dt))
            rows.append((k * dt, tip_now[1] - rest_tip_y))
    return np.array(rows)


def hub_motion(t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The FFRF frame's prescribed motion at t: position, rotation, velocity, angular velocity."""
    return np.zeros(3), rotation_z(hub_angle(t)), np.zeros(3), np.array([0.0, 0.0, hub_rate(t)])


def ffrf_deflection(
    cells: int, n_modes: int, dt: float, duration: float, stiffening: bool, times: np.ndarray
) -> np.ndarray:
    """Tip deflection [m] in the rotating frame of the FFRF body at `times` (NaN after it left
    the beam's length, i.e. diverged)."""
    body, root, tip = beam(cells, "corotational")
    fb = FloatingBody(body, craig_bampton(body, root, n_modes), stiffening=stiffening, dt=dt)
    fb.drive(hub_motion)
    t, y = [0.0], [0.0]
    for _ in range(round(duration / dt)):
        try:
            fb.step()
        except RuntimeError:  # the implicit iterations fail on a diverged linear body
            break
        t.append(fb.time)
        y.append(float(fb.displacements(tip).mean(axis=0)[1]))
        if abs(y[-1]) > DIVERGED:
            break
    out = np.interp(times, t, y)
    out[times > t[-1]] = np.nan
    return out


def timed(what: str, run: Callable[[], np.ndarray]) -> np.ndarray:
    t0 = time.perf_counter()
    result = run()
    print(f"{what}: {time.perf_counter() - t0:.1f} s")
    return result


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "spin-up")
    p.add_argument("--cells", type=int, default=20, help="Hex20 cells along the beam (default 20)")
    p.add_argument("--modes", type=int, default=8, help="normal modes of the FFRF basis (default 8)")
    p.add_argument("--dt", type=float, default=2e-3, help="the full runs' coarser step [s] (default 2e-3; also dt/2)")
    p.add_argument("--ffrf-dt", type=float, default=1e-3, help="the FFRF runs' step [s] (default 1e-3)")
    p.add_argument("--duration", type=float, default=DURATION, help=f"simulated time [s] (default {DURATION:g})")
    p.add_argument(
        "--model",
        choices=("stvk", "corotational", "both"),
        default="both",
        help="full runs' force model (default both)",
    )
    args = p.parse_args(argv)
    if args.cells < 2 or args.modes < 1:
        p.error("--cells must be >= 2 and --modes >= 1")
    if not (args.dt > 0 and args.ffrf_dt > 0 and args.duration >= 10 * args.dt):
        p.error("--dt and --ffrf-dt must be > 0 and --duration at least 10 steps of --dt")
    out = output_folder(args.out)

    models = ("stvk", "corotational") if args.model == "both" else (args.model,)
    columns: dict[str, np.ndarray] = {}
    times = np.empty(0)
    for model in models:
        coarse = timed(
            f"full {model}, dt {args.dt:g} s", lambda m=model: full_deflection(args.cells, args.dt, args.duration, m)
        )
        fine = timed(
            f"full {model}, dt {args.dt / 2:g} s",
            lambda m=model: full_deflection(args.cells, args.dt / 2, args.duration, m, every=2),
        )
        times = coarse[:, 0]
        columns[f"full {model} (extrapolated)"] = 2 * fine[:, 1] - coarse[:, 1]  # Richardson
        columns[f"full {model}, dt = {args.dt / 2:g} s"] = fine[:, 1]
    for stiffening in (True, False):
        name = f"FFRF, {args.modes} modes, " + ("stiffened" if stiffening else "linear")
        columns[name] = timed(
            name,
            lambda s=stiffening: ffrf_deflection(args.cells, args.modes, args.ffrf_dt, args.duration, s, times),
        )

    reference = columns[f"full {models[0]} (extrapolated)"]
    peak = float(np.abs(reference).max())
    k_peak = int(np.abs(reference).argmax())
    print(f"reference peak: {reference[k_peak]:.4f} m at {times[k_peak]:.2f} s")
    rows = []
    print("run | peak [m] | at t [s] | max |y - reference| / |reference peak| | diverged at t [s]")
    for name, y in columns.items():
        finite = np.isfinite(y)
        k = int(np.nanargmax(np.abs(y)))
        error = float(np.nanmax(np.abs(y - reference)) / peak)
        diverged = float(times[~finite][0]) if not finite.all() else float("nan")
        rows.append((name, float(y[k]), float(times[k]), error, diverged))
        print(f"{name} | {y[k]:.4f} | {times[k]:.2f} | {error:.4f} | {diverged:.2f}")
    write_csv(out / "summary.csv", ["run", "peak_m", "t_peak_s", "max_error_over_peak", "diverged_at_s"], rows)
    write_csv(
        out / "deflection.csv",
        ["t_s", *[f"{name} [m]" for name in columns]],
        np.column_stack([times, *columns.values()]).tolist(),
    )

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.8))
    styles = {
        "full stvk": ("k-", 3, 0.35),
        "full corotational": ("k:", 1.2, 1.0),
        "stiffened": ("C0-", 1.2, 1.0),
        "linear": ("C3--", 1.2, 1.0),
    }
    for name, y in columns.items():
        if "dt =" in name:
            continue  # backward Euler at dt/2 alone: its damping is what the extrapolation removes
        style, width, alpha = styles[name.split(" (")[0] if name.startswith("full") else name.rsplit(" ", 1)[1]]
        ax.plot(times, y, style, lw=width, alpha=alpha, label=name)
    ax.set_ylim(-1.6 * peak, 1.0 * peak)
    ax.axvline(RAMP, color="0.6", lw=0.8, ls=":")
    ax.annotate("hub at full speed", (RAMP, 0.85 * peak), fontsize=8, ha="center", color="0.4")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("tip deflection in the rotating frame [m]")
    ax.set_title(f"Spin-up beam: hub spun up to {OMEGA:g} rad/s over {RAMP:g} s")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    png = save_figure(fig, out / "spin_up_beam.png")
    print(f"wrote {out / 'deflection.csv'}, {out / 'summary.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
