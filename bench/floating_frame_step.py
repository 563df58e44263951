"""Time a FloatingBody step: a flexible link (Hex20, 1 x 0.1 x 0.1 m, E = 1e8 Pa) reduced to
--modes Craig-Bampton modes (its root face fixed: the frame), in three motions:

* tumbling: free flight with a spin about all three axes (below the first frequency, 32 rad/s)
  and every mode vibrating;
* pendulum: on a revolute joint, released horizontal under gravity, with geometric stiffening;
* spinning: driven at 6 rad/s about z by its hub (a prescribed motion, one Python call per step).

For each it prints the median time per step over --repeats runs of --steps steps, each from the
same start (the C++ loop
of FloatingBody.step(n); the driven motion steps from Python), the Newton iterations per step
and the real-time ratio (simulated seconds per wall second) at dt = 10 ms.

    taskset -c 1 python bench/floating_frame_step.py [--modes 20] [--steps 1000] [--repeats 7]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from bench_machine import describe_machine

import corotate as cr
from corotate.modal import FloatingBody, craig_bampton

DT = 0.01


def link(modes: int) -> tuple[cr.Body, object]:
    mesh = cr.box((1.0, 0.1, 0.1), cells=(12, 2, 2), element="hex20")
    body = cr.Body(mesh, cr.Material(E=1e8, nu=0.3, density=1000.0), model="linear")
    return body, craig_bampton(body, mesh.nodes_on_plane("x", 0.0), modes)


def hub(rate: float):
    def motion(t: float):
        c, s = np.cos(rate * t), np.sin(rate * t)
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return np.zeros(3), R, np.zeros(3), np.array([0.0, 0.0, rate])

    return motion


def scenarios(body, basis) -> dict[str, FloatingBody]:
    r = basis.size
    tumbling = FloatingBody(body, basis, stiffening=False, dt=DT)
    tumbling.set_state(
        velocity=(0.3, -0.2, 0.5), angular_velocity=(0.5, 1.0, 1.5), modal_velocities=np.linspace(0.1, -0.1, r)
    )
    pendulum = FloatingBody(body, basis, support="revolute", axis=(0, 1, 0), gravity=(0, 0, -9.81), dt=DT)
    spinning = FloatingBody(body, basis, dt=DT)
    spinning.set_state(angular_velocity=(0, 0, 6.0))
    spinning.drive(hub(6.0))
    return {"tumbling": tumbling, "pendulum": pendulum, "spinning": spinning}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--modes", type=int, default=20, help="modal coordinates r (default 20)")
    parser.add_argument("--steps", type=int, default=1000, help="steps per run (default 1000)")
    parser.add_argument("--repeats", type=int, default=7, help="runs per figure; the median is printed (default 7)")
    args = parser.parse_args(argv)
    body, basis = link(args.modes)
    print(describe_machine())
    print(f"floating frame step, {basis.size} modes, dt = {DT} s, {args.steps} steps x {args.repeats} runs")
    print(f"  {'motion':10s} {'us/step':>9s} {'iter/step':>10s} {'real time':>10s}")
    runs = [scenarios(body, basis) for _ in range(args.repeats)]  # each run from the same start
    for name in runs[0]:
        times, iterations = [], []
        for run in runs:
            fb = run[name]
            t0 = time.perf_counter()
            if name == "spinning":
                its = 0
                for _ in range(args.steps):
                    fb.step()
                    its += fb.last_iterations
            else:
                fb.step(args.steps)
                its = fb.last_iterations
            times.append((time.perf_counter() - t0) / args.steps)
            iterations.append(its / args.steps)
        t = float(np.median(times))
        print(f"  {name:10s} {1e6 * t:9.1f} {np.mean(iterations):10.2f} {DT / t:9.0f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
