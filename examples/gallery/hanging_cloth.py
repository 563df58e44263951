"""A mass-spring cloth pinned at two corners falls and swings (the paper's Fig. 1).

A 1 x 1 m cloth of n x n particles (structural, shear and bending springs, stiffness from
E = 0.5 MPa and 1 mm thickness) starts horizontal and is stepped explicitly (velocity
Verlet) in frames of 1/60 s, each split into as many substeps as the critical time step asks.

    python examples/gallery/hanging_cloth.py --out cloth   # hanging_cloth.png
"""

from __future__ import annotations

from pathlib import Path

from _gallery import arguments

import corotate as cr
from corotate.scenes import plot_springs

args = arguments(__doc__)

n, frames = (8, 30) if args.small else (24, 90)
cloth = cr.MassSpringBody.cloth(n, n, size=(1.0, 1.0), E=5e5, thickness=1e-3, density=200.0, bending=0.01, beta=1e-5)
sim = cr.ExplicitSimulation(cloth, dt=1 / 60, gravity=(0, 0, -9.81), mass_damping=1.5)
sim.fix([cloth.n_nodes - n, cloth.n_nodes - 1])  # the two corners of the edge y = 1
sim.step(frames)
print(
    f"{cloth.n_nodes} particles, {cloth.n_springs} springs; {frames} frames of 1/60 s, "
    f"{sim.stats['last_substeps']} substeps of {sim.critical_time_step:.2e} s per frame; "
    f"lowest point z = {sim.positions[:, 2].min():.2f} m"
)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)
png = plot_springs(cloth, sim.positions, out / "hanging_cloth.png", title=f"cloth at t = {sim.time:.2f} s")
print(f"wrote {png}")
