#!/usr/bin/env python3
"""A haptic loop: a device pushes a tool (the nodes of a small patch on the tip face of a
soft beam) up and down; the body steps at 100 Hz (co-rotational, implicit) while the force on
the device is queried 10 times per step (1 kHz) with the averaged-stiffness feedback (eq. 5),
whose local stiffness dF/dx lets a device render the contact stably between two queries.

    python examples/haptic_loop.py [--seconds 2] [--method averaged] [--csv trace.csv]

Prints the query rate the loop sustained, the time per query and per step, and the real-time
ratio; with --csv writes time, device displacement, force (x, y, z) and the contact stiffness
-dFz/dz at every query.
"""

from __future__ import annotations

import argparse
import csv
import time

import numpy as np

import corotate as cr


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated time (default 2 s)")
    parser.add_argument("--method", default="averaged", choices=["averaged", "corotational", "linear"])
    parser.add_argument("--queries", type=int, default=10, help="force queries per simulation step (default 10)")
    parser.add_argument("--csv", help="write the force trace here")
    args = parser.parse_args()

    mesh = cr.beam(1.0, 0.2, 0.2, cells=(24, 6, 6), element="tet4")  # 5,184 tets
    body = cr.Body(mesh, cr.Material(E=2e5, nu=0.4, density=1000.0))
    dt = 0.01
    sim = cr.Simulation(body, dt=dt, gravity=(0, 0, -9.81), rayleigh=(2.0, 0.0))
    p = mesh.points
    tool = np.flatnonzero(
        np.isclose(p[:, 0], 1.0) & (np.abs(p[:, 1] - 0.1) <= 0.034) & (np.abs(p[:, 2] - 0.1) <= 0.034)
    )
    sim.fix(np.concatenate([mesh.nodes_on_plane("x", 0.0), tool]))
    feedback = cr.HapticFeedback(body, tool, method=args.method)
    rest = p[tool].copy()

    def device(t: float) -> np.ndarray:  # the device's displacement: up and down by 15 cm
        return np.array([0.0, 0.0, 0.15 * np.sin(2 * np.pi * 0.5 * t)])

    steps = round(args.seconds / dt)
    trace = []
    query_time = step_time = 0.0
    x = sim.positions.copy()
    start = time.perf_counter()
    for s in range(steps):
        t0 = time.perf_counter()
        sim.positions[tool] = rest + device((s + 1) * dt)  # the tool where the device will be
        sim.velocities[tool] = (device((s + 1) * dt) - device(s * dt)) / dt
        sim.step()
        step_time += time.perf_counter() - t0
        x[:] = sim.positions
        for q in range(args.queries):  # haptic rate: the device moves on between two steps
            t = (s + 1) * dt + q * dt / args.queries
            x[tool] = rest + device(t)
            t0 = time.perf_counter()
            forces, stiffness = feedback.query(x)
            query_time += time.perf_counter() - t0
            # The contact stiffness -dFz/dz the device renders when the tool moves as one along z.
            k_zz = -stiffness[2::3, 2::3].sum()
            trace.append((t, device(t)[2], *forces.sum(axis=0), k_zz))
    wall = time.perf_counter() - start
    queries = steps * args.queries
    print(f"{mesh.n_cells} tets, tool of {tool.size} nodes ({feedback.num_elements} elements), method {args.method}")
    print(f"  {steps} steps of {dt} s and {queries} queries in {wall:.2f} s wall time")
    print(f"  query: {1e6 * query_time / queries:.1f} us  (force + {3 * tool.size}x{3 * tool.size} stiffness)")
    print(f"  step:  {1e3 * step_time / steps:.2f} ms")
    print(f"  query rate sustained: {queries / wall:.0f} Hz, real-time ratio {args.seconds / wall:.2f}")
    peak = max(abs(row[4]) for row in trace)
    stiffest = max(row[5] for row in trace)
    print(f"  peak vertical force on the device: {peak:.2f} N, contact stiffness up to {stiffest:.0f} N/m")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["time_s", "device_dz_m", "force_x_N", "force_y_N", "force_z_N", "stiffness_zz_N_per_m"])
            w.writerows(trace)
        print(f"  wrote {args.csv}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
