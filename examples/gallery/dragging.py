"""Dragging a body by one node: an attachment spring pulled along a circle.

The free end's top node of a soft cantilever is attached to a target by a stiff
zero-rest-length spring that is part of the implicit step (Simulation.attach), and the target
is moved every frame around a circle, as a mouse would. The node follows just behind the
target; the spring's pull is what the hand would feel.

    python examples/gallery/dragging.py --out dragging   # dragging.png
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from _gallery import arguments, save

import corotate as cr

args = arguments(__doc__)

mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000.0)), gravity=(0, 0, -9.81))
sim.fix(mesh.nodes_on_plane("x", 0.0))
node = mesh.nearest_node((2.0, 0.25, 0.5))
start = mesh.points[node]
sim.attach(node, start, stiffness=1e6)
frames = 50 if args.small else 200
targets, positions, pulls = [], [], []
for frame in range(frames):
    angle = 2 * np.pi * frame / 100  # one turn every 100 frames (5 s)
    target = start + 0.3 * np.array([0.0, np.sin(angle), 1 - np.cos(angle)])
    sim.move_attachments(node, target)
    sim.step(5)
    targets.append(target)
    positions.append(sim.positions[node].copy())
    pulls.append(np.linalg.norm(sim.attachment_forces()))
targets, positions = np.array(targets), np.array(positions)
lag = np.linalg.norm(positions - targets, axis=1)
print(f"{frames} frames: the node stays within {1e3 * lag.max():.1f} mm of the target; pull up to {max(pulls):.0f} N")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.plot(targets[:, 1], targets[:, 2], "k--", label="target")
left.plot(positions[:, 1], positions[:, 2], "C0-", label="dragged node")
left.set_aspect("equal")
left.set_xlabel("y [m]")
left.set_ylabel("z [m]")
left.legend()
left.set_title("The dragged node follows the target")
right.plot(0.05 * np.arange(1, frames + 1), pulls)
right.set_xlabel("t [s]")
right.set_ylabel("pull on the node [N]")
right.set_title("Attachment force")
save(fig, args.out, "dragging")
