"""Time a ModalBody: one implicit step with 20 modes (linear and with the reduced StVK
polynomial forces), recovering 300,000 DOFs (plain and with partial rotation), and projecting
nodal loads.

    taskset -c 1 python bench/modal_step.py [--modes 20] [--nodes 100000] [--repeats 7] [--cold]

The basis and the force tensors are random (the costs do not depend on their values); q stays
small so that the polynomial body stays stable. The nodes are scattered in a 10 x 1 x 1 m box;
the partial rotation has two domains (x < 4 m and x > 6 m, four representative points each)
blended over the 2 m between them, so a fifth of the nodes get a rotation of their own. Each
number is the median of --repeats runs.
Recovering every DOF is bound by memory bandwidth, which the other jobs on a shared machine
take their share of: those rows run interleaved, run by run, with the floor (NumPy summing the
float64 basis, i.e. reading it once) and a baseline (np.matmul into a preallocated array), and
print the median with the range of the runs. The 48 MB basis may stay in this machine's large
last-level cache between calls; --cold reads 1 GB before each call to evict it, as a frame
that does other work between recoveries would (the basis then comes from DRAM).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from corotate.modal import ModalBasis, ModalBody, PartialRotation


def median_time(fn, count: int, repeats: int) -> float:
    """Median over repeats of the mean seconds per call of count calls."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(count):
            fn()
        times.append((time.perf_counter() - t0) / count)
    return float(np.median(times))


def interleaved_times(fns: dict[str, object], repeats: int, evict: np.ndarray | None) -> dict[str, list[float]]:
    """Seconds of one call of each fn, repeats times, the fns taking turns within each run;
    before each call the array evict (if given) is read to push the data out of the caches."""
    times: dict[str, list[float]] = {name: [] for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            if evict is not None:
                evict.sum()
            t0 = time.perf_counter()
            fn()  # type: ignore[operator]
            times[name].append(time.perf_counter() - t0)
    return times


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--modes", type=int, default=20, help="modal coordinates r")
    parser.add_argument("--nodes", type=int, default=100_000, help="nodes to recover (3 DOFs each)")
    parser.add_argument("--repeats", type=int, default=7, help="runs per measurement (median)")
    parser.add_argument("--cold", action="store_true", help="evict the basis from the caches before each recovery")
    args = parser.parse_args(argv)
    r, n = args.modes, args.nodes
    rng = np.random.default_rng(0)
    rest = rng.uniform(0.0, 1.0, size=(n, 3)) * [10.0, 1.0, 1.0]
    basis = ModalBasis(
        vectors=np.ascontiguousarray(rng.normal(size=(3 * n, r)) / np.sqrt(3 * n)),
        eigenvalues=np.sort(rng.uniform(1.0, 1e4, r)),
        rest_positions=rest,
        fixed_dofs=np.zeros(0, dtype=np.int64),
        interface_nodes=np.zeros(0, dtype=np.int64),
        n_normal_modes=r,
    )
    A = 1e-2 * rng.normal(size=(r, r, r))
    B = 1e-3 * rng.normal(size=(r, r, r, r))
    linear = ModalBody(basis, dt=1e-3, rayleigh=(1.0, 0.0))
    single = ModalBody(basis, dt=1e-3, rayleigh=(1.0, 0.0), recovery="float32")
    poly = ModalBody(basis, dt=1e-3, rayleigh=(1.0, 0.0), quadratic=A, cubic=B)
    domains = [np.flatnonzero(rest[:, 0] < 4.0), np.flatnonzero(rest[:, 0] > 6.0)]
    turned = ModalBody(
        basis, partial_rotation=PartialRotation(rest, domains, [d[:4] for d in domains], blend_distance=1.0)
    )
    for body in (linear, poly):
        body.q[:] = 1e-3 * rng.normal(size=r)
    out = np.empty((n, 3))
    flat = out.reshape(-1)
    subset = np.sort(rng.choice(n, 1000, replace=False))
    part = np.empty((subset.size, 3))
    loaded = np.arange(10)
    forces = rng.normal(size=(10, 3))

    K = np.diag(basis.eigenvalues)
    C = np.eye(r)
    dt = 1e-3
    q, v = 1e-3 * rng.normal(size=r), np.zeros(r)

    def numpy_step() -> None:
        nonlocal q, v
        dv = np.linalg.solve(np.eye(r) + dt * C + dt * dt * K, dt * (-K @ q - C @ v) - dt * dt * K @ v)
        v = v + dv
        q = q + dt * v

    rows = [
        ("linear modal step (C++, 1000 steps per call)", lambda: linear.step(1000), 1000, 20),
        ("linear modal step (one step per Python call)", lambda: linear.step(1), 1, 2000),
        ("baseline: the same step in NumPy", numpy_step, 1, 2000),
        ("polynomial StVK modal step (C++, 100 steps per call)", lambda: poly.step(100), 100, 20),
        ("polynomial StVK modal step (one step per Python call)", lambda: poly.step(1), 1, 200),
        ("recover 1,000 chosen nodes into out", lambda: linear.displacements(subset, out=part), 1, 2000),
        ("project loads on 10 nodes", lambda: linear.apply_forces(loaded, forces), 1, 2000),
    ]
    print(f"ModalBody, r = {r} modes, {3 * n:,} DOFs; median of {args.repeats} runs")
    for name, fn, steps, count in rows:
        # Thousands of damped steps decay q towards subnormal numbers, whose products cost
        # ~100 cycles each: recover a q of ordinary size.
        linear.q[:] = single.q[:] = 1e-3 * rng.normal(size=r)
        seconds = median_time(fn, count, args.repeats) / steps
        print(f"  {name:56s} {1e6 * seconds:10.2f} us")
    linear.q[:] = single.q[:] = turned.q[:] = 1e-3 * rng.normal(size=r)
    vectors = basis.vectors.reshape(-1)
    recovery = {
        f"floor: read the {vectors.nbytes / 1e6:.0f} MB float64 basis once (np.sum)": vectors.sum,
        f"recover all {3 * n:,} DOFs into out": lambda: linear.displacements(out=out),
        f"baseline: np.matmul(Phi, q, out=) of {3 * n:,} DOFs": lambda: np.matmul(basis.vectors, linear.q, out=flat),
        f"recover all {3 * n:,} DOFs, float32 basis": lambda: single.displacements(out=out),
        f"recover all {3 * n:,} DOFs with partial rotation": lambda: turned.displacements(out=out),
    }
    evict = np.ones(1 << 27) if args.cold else None  # 1 GB
    cache = "cold (basis evicted before each call)" if args.cold else "warm"
    print(f"  recovery, interleaved, {cache}: median [min - max] of {3 * args.repeats} runs")
    for name, times in interleaved_times(recovery, 3 * args.repeats, evict).items():
        lo, mid, hi = np.percentile(1e3 * np.array(times), [0, 50, 100])
        print(f"  {name:56s} {mid:7.2f} ms [{lo:.2f} - {hi:.2f}]")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
