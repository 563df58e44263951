"""A flexible body in a few modes: a reduced cantilever against the full simulation.

A Hex20 cantilever (8 x 1 x 1 m, E = 10 MPa) is reduced by Craig-Bampton to six fixed-
interface normal modes plus the constraint modes of its loaded tip node: 9 coordinates for
312 unknowns. A tip load is switched on at t = 0; the reduced body swings beside the full
co-rotational simulation of the same mesh, each step a 9 x 9 solve instead of a 312 x 312 one.

    python examples/gallery/modal_beam.py --out modal   # modal_beam.png
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from _gallery import arguments, save

import corotate as cr
from corotate.modal import ModalBody, craig_bampton

args = arguments(__doc__)

mesh = cr.beam(8.0, 1.0, 1.0, cells=(8, 1, 1), element="hex20")
material = cr.Material(E=1e7, nu=0.3, density=1000.0)
clamp = mesh.nodes_on_plane("x", 0.0)
tip = mesh.nearest_node((8.0, 0.5, 1.0))
force = np.array([0.0, 0.0, -2000.0])
frames = 40 if args.small else 150

basis = craig_bampton(cr.Body(mesh, material, model="linear"), clamp, n_modes=6, interface_nodes=[tip])
modal = ModalBody(basis, dt=0.01, rayleigh=(0.5, 0.0))
modal.apply_forces([tip], force)
tip_z = []
for _ in range(frames):
    modal.step(5)
    tip_z.append(modal.displacements([tip])[0, 2])
curves = {"modal": np.array(tip_z)}

sim = cr.Simulation(cr.Body(mesh, material), dt=0.01, rayleigh=(0.5, 0.0), solver=cr.Direct())
sim.fix(clamp)
sim.external_forces[tip] = force
full = []
for _ in range(frames):
    sim.step(5)
    full.append(sim.displacements[tip, 2])
curves["full co-rotational"] = np.array(full)

t = 0.05 * np.arange(1, frames + 1)
for name, z in curves.items():
    print(f"{name:20s} lowest tip z {z.min():+.3f} m, at the end {z[-1]:+.3f} m")
print(f"{basis.size} basis vectors for {3 * mesh.n_nodes} unknowns")
fig, ax = plt.subplots(figsize=(7, 4))
for (name, z), style in zip(curves.items(), ("C1--", "k-")):
    ax.plot(t, z, style, label=name)
ax.set_xlabel("t [s]")
ax.set_ylabel("tip z displacement [m]")
ax.set_title(f"Cantilever under a tip load: {basis.size} modal coordinates against {3 * mesh.n_nodes} unknowns")
ax.grid(alpha=0.3)
ax.legend()
save(fig, args.out, "modal_beam")
