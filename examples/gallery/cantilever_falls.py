"""A soft cantilever falls under its own weight: linear against co-rotational FEM.

The same 5 x 1 x 1 m beam (E = 1 MPa, clamped at x = 0) is stepped with both force models.
Linear FEM moves each point along the tangent of its small-displacement path, so the swinging
tip runs straight down and the beam stretches; co-rotational FEM turns each element's
stiffness with the element, and the tip swings on an arc of about the beam's length.

    python examples/gallery/cantilever_falls.py --out cantilever   # cantilever_falls.png
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from _gallery import arguments, save

import corotate as cr

args = arguments(__doc__)

cells, frames = ((10, 2, 2), 20) if args.small else ((20, 4, 4), 60)
mesh = cr.beam(5.0, 1.0, 1.0, cells=cells)
material = cr.Material(E=1e6, nu=0.3, density=1000.0)
tip = mesh.nodes_on_plane("x", 5.0)
fig, ax = plt.subplots(figsize=(6, 5))
for model, style in (("linear", "C3--"), ("corotational", "C0-")):
    sim = cr.Simulation(cr.Body(mesh, material, model=model), dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    path = [sim.positions[tip].mean(axis=0)]
    for _ in range(frames):
        sim.step(5)  # five steps of 0.01 s per frame
        path.append(sim.positions[tip].mean(axis=0))
    path = np.array(path)
    reach = np.linalg.norm(path[:, [0, 2]] - [0.0, 0.5], axis=1).max()
    print(
        f"{model:13s} tip after {sim.time:.1f} s at x = {path[-1, 0]:.2f} m, z = {path[-1, 2]:.2f} m; "
        f"farthest from the clamp's centre {reach:.2f} m"
    )
    ax.plot(path[:, 0], path[:, 2], style, label=f"{model}: tip path")
    ax.plot(sim.positions[:, 0], sim.positions[:, 2], ".", color=style[:2], ms=2)
ax.add_patch(plt.Circle((0.0, 0.5), 5.0, fill=False, color="0.6", linestyle=":"))
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("z [m]")
ax.set_title(f"Cantilever under gravity, {mesh.n_cells} tets, t = {sim.time:.1f} s")
ax.legend(loc="lower left")
save(fig, args.out, "cantilever_falls")
