"""Hertz contact: an elastic ball pressed on a rigid frictionless plane. How close is corotate's
node-based contact to Hertz's force-indentation law F = (4/3) E* sqrt(R) d^(3/2)
(E* = E / (1 - nu^2) for a rigid plane), and what separates them: the mesh, or the ball?

The setup: a ball of radius R squeezed between two frictionless plates is symmetric about its
equator, whose plane stays plane and carries no shear. Half of it is simulated: the hemisphere
below the equator, its pole on a fixed frictionless plane (the ground), its flat equatorial cut
pushed down by a second frictionless plane (a roller support: the cut moves down as a plane and
slides freely in it). The indentation d is the approach of the cut plane to the ground (the
plate's travel less the pole's depth in the ground), the force the ground's contact force. The
one-sided plate is an exact roller only where the equator's plane is in compression: 8-13 % of
the cut's nodes, at its rim, lift off (the ball's equator carries vertical tension near its
surface), which makes the hemisphere a little softer than the ball. Loading is quasi-static:
backward Euler with dt far above the ball's period (each step is a static solve with the
contact's active set), the plate moved in a few steps to each indentation and held until the
force settles.

The mesh: a half-cube mapped onto the half-ball (the smooth cube-to-ball map), graded towards
the pole by scaling every point of the half-cube along its ray from the pole's pre-image by
t^(p-1) (t in [0, 1] the ray's gauge): the cells near the contact shrink like sqrt(distance)
for p = 2 and keep their shape. Tet4 (each hex in 6 tets), Tet10 (straight mid-edge nodes,
those on the sphere moved onto it) or Hex8.

What Hertz predicts for this measurement: Hertz's d is the approach of distant points of two
half-spaces; the ball has none. The approach of the equator's plane, d_c, is smaller, because
the ball's bulk between the contact and the equator is stiffer than the half-space it stands for.
The script computes that exactly for linear elasticity: the ball loaded at both poles by Hertz's
pressure for the force F (vertical traction, per projected area p0 sqrt(1 - r^2/a^2)), solved as
a Legendre series of the sphere's traction problem (checked: uniaxial stress exact; high orders
reproduce the half-space). Its pole-to-equator approach is d_c = d_Hertz(F) - kappa F / (E R),
kappa = 0.22-0.25 (nu = 0.3) for d up to 5 % of R: the ball carries 5 % more than Hertz at
d_c = 1 % R and 14 % more at 5 % R. (The half-space's own estimate, Boussinesq's displacement at
depth R, doubles kappa; the spherical rather than paraboloidal profile changes F by 0.5 % at 5 %.)
The table gives each run's largest error against both over the checked range.

    python -m studies.hertz_contact --out hertz-contact   # hertz_contact.csv, hertz_contact.png
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from numpy.polynomial.legendre import leggauss

import corotate as cr

from ._common import output_folder, parser, pyplot, save_figure, write_csv

R = 0.05  # [m] the ball's radius
MATERIAL = cr.Material(E=1e6, nu=0.3, density=1000.0)
E_STAR = MATERIAL.E / (1 - MATERIAL.nu**2)
ELEMENTS = ("tetra", "tetra10", "hexahedron")
# The six tets of a hex cell around its diagonal 0-6 (VTK corner order): conforming between cells.
KUHN = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6], [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
TET_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # tetra10's mid-edge node order
HEX_CORNERS = ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))


def hertz_force(d: np.ndarray | float, radius: float = R) -> np.ndarray:
    """Hertz's force [N] of a ball on a rigid plane at approach d [m]."""
    return 4.0 / 3.0 * E_STAR * np.sqrt(radius) * np.asarray(d) ** 1.5


def _half_cube_to_ball(c: np.ndarray, grading: float) -> np.ndarray:
    """Points of the half-cube [-1, 1]^2 x [-1, 0] graded towards (0, 0, -1) and mapped onto the
    unit half-ball (z <= 0): faces x, y = +-1 and z = -1 onto the sphere, z = 0 onto the cut."""
    x, y, z = c[:, 0], c[:, 1], c[:, 2] + 1.0
    t = np.maximum(np.maximum(np.abs(x), np.abs(y)), z)  # the gauge of the ray from the pole
    s = np.where(t > 0, t ** (grading - 1.0), 0.0)
    x, y, z = x * s, y * s, z * s - 1.0
    return np.column_stack(
        [
            x * np.sqrt(1 - y**2 / 2 - z**2 / 2 + y**2 * z**2 / 3),
            y * np.sqrt(1 - z**2 / 2 - x**2 / 2 + z**2 * x**2 / 3),
            z * np.sqrt(1 - x**2 / 2 - y**2 / 2 + x**2 * y**2 / 3),
        ]
    )


def hemisphere(n: int, element: str = "tetra10", grading: float = 2.0, radius: float = R) -> cr.Mesh:
    """The lower half-ball of `radius` (pole at z = -radius, cut at z = 0): n x n x n/2 hex cells
    of the graded half-cube, as `element` cells ("tetra": 6 per hex, "tetra10", "hexahedron")."""
    if n < 2 or n % 2:
        raise ValueError(f"n must be even and >= 2, got {n}")
    i, k = np.arange(n + 1), np.arange(n // 2 + 1)
    grid = np.stack(np.meshgrid(i, i, k, indexing="ij"), axis=-1).reshape(-1, 3)
    param = -1.0 + 2.0 * grid / n
    points = radius * _half_cube_to_ball(param, grading)
    a, b, c = (g.ravel() for g in np.meshgrid(np.arange(n), np.arange(n), np.arange(n // 2), indexing="ij"))
    corners = np.column_stack([((a + dx) * (n + 1) + b + dy) * (n // 2 + 1) + c + dz for dx, dy, dz in HEX_CORNERS])
    cells = corners if element == "hexahedron" else corners[:, KUHN].reshape(-1, 4)
    if element == "tetra10":
        # Straight mid-edge nodes (the graded map is too curved near the pole for mapped ones),
        # those of edges on the sphere moved onto it: the surface is quadratic, the cells not bent.
        key = np.sort(cells[:, np.array(TET_EDGES)], axis=2).reshape(-1, 2)
        edges, which = np.unique(key, axis=0, return_inverse=True)
        mid = 0.5 * (points[edges[:, 0]] + points[edges[:, 1]])
        pm = 0.5 * (param[edges[:, 0]] + param[edges[:, 1]])
        on_sphere = (np.abs(pm[:, 0]) > 1 - 1e-12) | (np.abs(pm[:, 1]) > 1 - 1e-12) | (pm[:, 2] < -1 + 1e-12)
        mid[on_sphere] *= radius / np.linalg.norm(mid[on_sphere], axis=1, keepdims=True)
        cells = np.column_stack([cells, len(points) + which.reshape(len(cells), len(TET_EDGES))])
        points = np.vstack([points, mid])
    elif element not in ELEMENTS:
        raise ValueError(f"element must be one of {ELEMENTS}, got {element!r}")
    return cr.Mesh(points, cells, element)


def surface_nodes(mesh: cr.Mesh, radius: float = R) -> np.ndarray:
    """Every node on the sphere or the cut, the mid-edge nodes of quadratic cells included (the
    default contact nodes are the corners of the boundary faces only: a Tet10's mid-edge nodes
    would sink into the ground)."""
    p = mesh.points
    return np.flatnonzero(
        np.isclose(np.linalg.norm(p, axis=1), radius, rtol=1e-9) | np.isclose(p[:, 2], 0.0, atol=1e-12 * radius)
    )


def press(
    mesh: cr.Mesh,
    indentations: Sequence[float],
    model: str = "corotational",
    radius: float = R,
    ramp: int = 2,
    settle: float = 1e-4,
    max_hold: int = 12,
) -> np.ndarray:
    """(k, 3) rows (d [m], F [N], share of the cut's nodes off the plate): the hemisphere `mesh`
    pressed between the ground (at its pole) and the plate (at its cut) to each indentation of
    `indentations` (fractions of the radius, increasing). The plate moves there in `ramp` steps;
    the steps go on until the ground's force changes by less than `settle` (relative) from one
    to the next (at most max_hold steps)."""
    body = cr.Body(mesh, MATERIAL, model=model)
    # dt = 1 s against a period of ~2 ms: each step is a static solve; the mass damping takes
    # out what motion the ramp leaves. The frictionless plates exert no lateral force or torque
    # about z, so the ball's free rigid motions in the plane are never excited.
    sim = cr.Simulation(body, dt=1.0, solver=cr.Direct(), rayleigh=(1.0, 0.0))
    sim.contact_nodes = surface_nodes(mesh, radius)
    eps = 1e-12 * radius  # the planes a hair off the surface: no node starts inside them
    ground = cr.Plane(point=(0.0, 0.0, -radius - eps), normal=(0.0, 0.0, 1.0))
    plate = cr.Plane(point=(0.0, 0.0, eps), normal=(0.0, 0.0, -1.0))
    sim.add_obstacle(ground)
    sim.add_obstacle(plate)
    cut = np.flatnonzero(np.isclose(mesh.points[:, 2], 0.0, atol=eps))
    rows, z = [], 0.0
    for fraction in indentations:
        target = -fraction * radius
        for s in range(1, ramp + 1):
            plate.move_to((0.0, 0.0, z + (target - z) * s / ramp))
            sim.step()
        z = target
        force = sim.contact_force(ground)[2]
        for _ in range(max_hold):
            sim.step()
            last, force = force, sim.contact_force(ground)[2]
            if abs(force - last) <= settle * abs(force):
                break
        x = sim.positions
        # The plate's travel less how deep the pole sits in the ground: the cut's rim lifts off
        # the plate (the ball's equator carries vertical tension near its surface, which a
        # one-sided plate cannot hold), so the cut nodes' mean height would overstate d.
        rows.append((-z - (-radius - x[:, 2].min()), force, np.mean(x[cut, 2] < z - 1e-6 * radius)))
    return np.array(rows)


def ball_pole_approach(a: float, radius: float = R, n_max: int = 3000) -> tuple[float, float]:
    """(F [N], d_c [m]): a linear elastic ball loaded at both poles by Hertz's pressure of
    contact radius a (vertical traction, p0 sqrt(1 - r^2/a^2) per projected area) and the
    approach of each pole to the equator's plane, from the Legendre series of the sphere's
    axisymmetric traction problem (even orders up to n_max; the sum converges like n^-3/2).

    Each order n >= 2 combines the two solutions regular at the centre, grad(r^n P_n) and
    r^2 grad(w) - beta x w (w = r^n P_n, beta from Navier's equation), to the surface traction's
    radial and tangential parts; n = 0 is the uniform pressure."""
    E, nu = MATERIAL.E, MATERIAL.nu
    mu, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    force = 4 * E_STAR * a**3 / (3 * radius)
    p0 = 3 * force / (2 * np.pi * a**2)
    x, w = leggauss(400)  # over the cap: r = R sin(psi) = a sin(phi), phi in [0, pi/2]
    phi, w = 0.25 * np.pi * (x + 1), 0.25 * np.pi * w
    psi = np.arcsin(a * np.sin(phi) / radius)
    c, s = np.cos(psi), np.sin(psi)
    weight = w * a * np.cos(phi) / (radius * c) * s  # sin(psi) dpsi
    p = p0 * np.cos(phi)
    radial, tangential = -p * c**2, p * c * s  # -p cos(psi) e_z per sphere area
    approach = 0.0
    prev, cur, dprev, dcur = np.ones_like(c), c.copy(), np.zeros_like(c), np.ones_like(c)  # P_n and dP_n/dc
    for n in range(n_max + 1):
        if n >= 2:
            prev, cur, dprev, dcur = cur, ((2 * n - 1) * c * cur - (n - 1) * prev) / n, dcur, n * cur + c * dcur
        if n % 2:
            continue
        pn_at, dpn = (prev, dprev) if n == 0 else (cur, dcur)
        p_n = (2 * n + 1) * np.sum(weight * radial * pn_at)  # both poles: twice the one cap's
        if n == 0:
            approach += p_n * radius / (3 * lam + 2 * mu)
            continue
        q_n = (2 * n + 1) / (n * (n + 1)) * np.sum(weight * tangential * (-s * dpn))
        beta = ((1 - 2 * nu) * (4 * n + 2) + 2 * n) / (n + 5 - 4 * nu)
        m = np.array(
            [
                [
                    2 * mu * (n - 1) * n,
                    lam * (2 * n - beta * (n + 3)) + mu * (2 * n - beta * (n + 2)) + mu * (2 * n - beta) * n,
                ],
                [2 * mu * (n - 1), mu * (2 * n - beta)],
            ]
        )
        A, B = np.linalg.solve(m, [p_n, q_n])
        approach += (A * n + B * (n - beta)) * radius
    return force, -approach


def ball_force(d: np.ndarray, radius: float = R) -> np.ndarray:
    """The linear elastic ball's force [N] at pole-to-equator approach d [m] (ball_pole_approach,
    inverted by interpolation on a table of contact radii)."""
    radii = np.linspace(0.02, 0.3, 40) * radius
    table = np.array([ball_pole_approach(a, radius) for a in radii])
    return np.interp(np.asarray(d), table[:, 1], table[:, 0])


def main(argv: Sequence[str] | None = None) -> int:
    p = parser(__doc__, "hertz-contact")
    p.add_argument(
        "--runs",
        nargs="+",
        default=["tetra:12", "tetra:16", "tetra:24", "hexahedron:12", "hexahedron:16", "tetra10:8", "tetra10:12"],
        help="element:n pairs, n the cells across the half-cube (even) (default: a Tet4, Hex8 and Tet10 series)",
    )
    p.add_argument("--model", default="corotational", help="the force model (default corotational)")
    p.add_argument("--grading", type=float, default=2.0, help="the mesh's grading towards the pole (default 2)")
    p.add_argument(
        "--indentations",
        type=float,
        nargs="+",
        default=[0.01, 0.02, 0.03, 0.04, 0.05],
        help="indentations d / R (default 0.01 ... 0.05)",
    )
    args = p.parse_args(argv)
    runs = []
    for item in args.runs:
        element, _, n = item.partition(":")
        if element not in ELEMENTS or not n.isdigit() or int(n) < 2 or int(n) % 2:
            p.error(f"--runs: {item!r} is not element:n with element one of {ELEMENTS} and n even")
        runs.append((element, int(n)))
    if not (args.grading >= 1):
        p.error("--grading must be >= 1")
    fractions = sorted(args.indentations)
    if not all(0 < f <= 0.2 for f in fractions):
        p.error("--indentations must be in (0, 0.2]")
    out = output_folder(args.out)

    d_fine = np.linspace(0.0, max(fractions) * 1.05, 200) * R
    ball = ball_force(d_fine[1:])
    rows, curves = [], []
    print("element | n | nodes | cells | max |F/F_Hertz - 1| | max |F/F_ball - 1| | runtime [s]")
    for element, n in runs:
        mesh = hemisphere(n, element, args.grading)
        t0 = time.perf_counter()
        result = press(mesh, fractions, args.model)
        runtime = time.perf_counter() - t0
        d, force = result[:, 0], result[:, 1]
        to_hertz = force / hertz_force(d) - 1
        to_ball = force / np.interp(d, d_fine[1:], ball) - 1
        curves.append((f"{element}, n = {n} ({mesh.n_nodes} nodes)", d, force))
        for dk, fk, eh, eb in zip(d, force, to_hertz, to_ball):
            rows.append((element, n, mesh.n_nodes, mesh.n_cells, dk / R, fk, eh, eb, runtime))
        worst_h, worst_b = np.abs(to_hertz).max(), np.abs(to_ball).max()
        print(f"{element} | {n} | {mesh.n_nodes} | {mesh.n_cells} | {worst_h:.3f} | {worst_b:.3f} | {runtime:.0f}")
        print("   d/R:", " ".join(f"{v:.4f}" for v in d / R), " F/F_Hertz:", " ".join(f"{v:.3f}" for v in 1 + to_hertz))
    header = ["element", "n", "nodes", "cells", "d_over_R", "force_N", "error_to_hertz", "error_to_ball", "runtime_s"]
    write_csv(out / "hertz_contact.csv", header, rows)

    plt = pyplot()
    fig, (ax, ax_ratio) = plt.subplots(1, 2, figsize=(11, 4.6))
    ax.plot(d_fine / R, hertz_force(d_fine), "k-", lw=2, label="Hertz, $(4/3) E^* \\sqrt{R} d^{3/2}$")
    ax.plot(d_fine[1:] / R, ball, "k--", lw=1.5, label="linear elastic ball under Hertz's pressure")
    ax_ratio.plot(d_fine[1:] / R, ball / hertz_force(d_fine[1:]), "k--", lw=1.5, label="ball under Hertz's pressure")
    ax_ratio.axhspan(0.95, 1.05, color="0.85", label="Hertz +- 5 %")
    for name, d, force in curves:
        (line,) = ax.plot(d / R, force, "o", ms=4, label=name)
        ax_ratio.plot(d / R, force / hertz_force(d), "o-", ms=4, lw=1, color=line.get_color(), label=name)
    ax.set_xlabel("indentation d / R (approach of the equator to the plane)")
    ax.set_ylabel("force F [N]")
    ax.set_title(f"Ball on a rigid plane (R = {R * 1e3:g} mm, E = {MATERIAL.E:g} Pa, nu = {MATERIAL.nu:g})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax_ratio.set_xlabel("indentation d / R")
    ax_ratio.set_ylabel("F / F_Hertz")
    ax_ratio.set_title(f"Force over Hertz's ({args.model} model)")
    ax_ratio.grid(alpha=0.3)
    ax_ratio.legend(fontsize=7)
    png = save_figure(fig, out / "hertz_contact.png")
    print(f"wrote {out / 'hertz_contact.csv'} and {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
