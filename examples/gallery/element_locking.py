"""Which element for bending: tip deflection of a cantilever against mesh refinement.

A 10 x 1 x 1 m cantilever (E = 1e7 Pa, nu = 0.3), clamped at x = 0, carries a
small tip load (linear statics). Linear tetrahedra (Tet4) and trilinear hexahedra (Hex8)
cannot represent the linear variation of bending strain across an element, and resist bending
with spurious shear: coarse meshes of them are too stiff ("locking"). Quadratic hexahedra
(Hex20) bend correctly with one element through the thickness. The reference is the finest
Hex20 mesh; Timoshenko beam theory is printed beside it.

    python examples/gallery/element_locking.py --out locking   # element_locking.png
"""

from __future__ import annotations

import matplotlib.pyplot as plt
from _gallery import arguments, save

import corotate as cr

args = arguments(__doc__)

L, H, LOAD = 10.0, 1.0, 100.0  # m, m, N
material = cr.Material(E=1e7, nu=0.3, density=1000.0)


def tip_deflection(element: str, n: int) -> tuple[int, float]:
    """Unknowns and mean tip deflection [m] of the cantilever meshed with 10n x n x n cubes."""
    mesh = cr.beam(L, H, H, cells=(10 * n, n, n), element=element)
    sim = cr.Simulation(cr.Body(mesh, material, model="linear"), solver=cr.Direct())
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    tip = mesh.nodes_on_plane("x", L)
    sim.external_forces[tip, 2] = -LOAD / tip.size
    sim.solve_static()
    return 3 * mesh.n_nodes, float(-sim.displacements[tip, 2].mean())


EI, GA = material.E * H**4 / 12, material.E / (2 * (1 + material.nu)) * H * H
timoshenko = LOAD * L**3 / (3 * EI) + LOAD * L / (5 / 6 * GA)
sizes = {"tet4": (1, 2) if args.small else (1, 2, 4), "hex8": (1, 2) if args.small else (1, 2, 4)}
sizes["hex20"] = (1, 2) if args.small else (1, 2, 3)
results = {e: [tip_deflection(e, n) for n in ns] for e, ns in sizes.items()}
reference = results["hex20"][-1][1]
print(
    f"reference (Hex20 {10 * sizes['hex20'][-1]} x {sizes['hex20'][-1]} x {sizes['hex20'][-1]}): "
    f"{1e3 * reference:.3f} mm; Timoshenko beam theory {1e3 * timoshenko:.3f} mm"
)
fig, ax = plt.subplots(figsize=(6, 4.5))
for element, rows in results.items():
    for n, (dofs, w) in zip(sizes[element], rows):
        print(
            f"{element:6s} {10 * n:3d} x {n} x {n}: {dofs:6d} unknowns, {1e3 * w:7.3f} mm, "
            f"{100 * (1 - w / reference):5.1f} % less than converged"
        )
    ax.plot([d for d, _ in rows], [w / reference for _, w in rows], "o-", label=element)
ax.axhline(1.0, color="k", linewidth=0.8)
ax.set_xscale("log")
ax.set_xlabel("unknowns (3 x nodes)")
ax.set_ylabel("tip deflection / converged")
ax.set_title("Cantilever 10 x 1 x 1 m under a tip load: locking of linear elements")
ax.grid(alpha=0.3)
ax.legend()
save(fig, args.out, "element_locking")
