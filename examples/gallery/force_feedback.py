"""What a haptic device feels: the force at a tool pushed into a soft beam.

The nodes of the free end face of a clamped beam are the tool; a device lifts them by 0.3 m
while the body steps at 100 Hz. Between steps the force on the tool is queried as a haptic
loop would (HapticFeedback), by the three methods: linear, co-rotational (eq. 3) and the
paper's averaged stiffness (eq. 5), which follows the stiffening a large bend brings.

    python examples/gallery/force_feedback.py --out feedback   # force_feedback.png
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from _gallery import arguments, save

import corotate as cr

args = arguments(__doc__)

cells, steps = ((6, 2, 2), 30) if args.small else ((12, 3, 3), 100)
mesh = cr.beam(1.0, 0.2, 0.2, cells=cells, element="tet4")
body = cr.Body(mesh, cr.Material(E=2e5, nu=0.4, density=1000))
sim = cr.Simulation(body, dt=0.01, rayleigh=(5.0, 0.0))
tool = mesh.nodes_on_plane("x", 1.0)
sim.fix(np.concatenate([mesh.nodes_on_plane("x", 0.0), tool]))
methods = ("linear", "corotational", "averaged")
feedback = {m: cr.HapticFeedback(body, tool, method=m) for m in methods}
lift = np.linspace(0.0, 0.3, steps + 1)[1:]
forces = {m: [] for m in methods}
for height in lift:
    sim.positions[tool, 2] = mesh.points[tool, 2] + height  # the device moves the tool
    sim.step()
    for m in methods:
        f, _stiffness = feedback[m].query(sim.positions)  # forces on the tool nodes, and dF/dx
        forces[m].append(-f[:, 2].sum())  # what the device must push with
for m in methods:
    print(f"{m:13s} at {lift[-1]:.2f} m: {forces[m][-1]:7.1f} N")
print(f"{feedback['averaged'].num_elements} elements around the {tool.size}-node tool")
fig, ax = plt.subplots(figsize=(6, 4))
for m, style in zip(methods, ("k--", "C0-", "C2-")):
    ax.plot(lift, forces[m], style, label=m)
ax.set_xlabel("tool lifted by [m]")
ax.set_ylabel("force the device pushes with [N]")
ax.set_title("Force feedback at a tool, three methods")
ax.grid(alpha=0.3)
ax.legend()
save(fig, args.out, "force_feedback")
