"""Static equilibrium under prescribed displacements (displacement control)."""

import numpy as np
import pytest

import corotate as cr


def guided_cantilever(model, cells=(10, 1, 1), length=10.0):
    mesh = cr.beam(length, 1.0, 1.0, cells=cells, element="hex20")
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.0, density=1000.0), model=model)
    sim = cr.Simulation(body)
    root, tip = mesh.nodes_on_plane("x", 0.0), mesh.nodes_on_plane("x", length)
    sim.fix(np.concatenate([root, tip]))
    return mesh, sim, tip


def test_prescribed_tip_translation_gives_the_guided_beam_reaction():
    # The whole tip face translated by delta in z and kept from rotating: a fixed-guided beam,
    # delta = P L^3 / (12 E I) + P L / (kappa G A). The reaction is the internal force the
    # model reports on the prescribed nodes.
    L, E, delta = 10.0, 1e7, 0.01
    _mesh, sim, tip = guided_cantilever("linear", length=L)
    target = sim.positions.copy()
    target[tip, 2] += delta
    result = sim.solve_static(load_steps=1, prescribed=target)
    np.testing.assert_allclose(sim.positions[tip], target[tip], rtol=0, atol=1e-14)
    assert result["residual_history"][0][-1] <= 1e-8
    reaction = -sim.internal_forces()[tip, 2].sum()  # force that holds the tip there
    I, A, G, kappa = 1.0 / 12.0, 1.0, E / 2.0, 10.0 / 12.0
    P = delta / (L**3 / (12 * E * I) + L / (kappa * G * A))
    assert reaction == pytest.approx(P, rel=0.03)


def test_large_prescribed_displacement_is_reached_in_load_steps():
    # A 1.5 m sideways shift of the tip of a 10 m co-rotational beam: ramped over load steps,
    # every step converges, the tip ends where it was told to, and the antisymmetric S-shape
    # puts mid-span at half the shift. (At 3 m the R K R^T tangent, which leaves out the
    # derivative of the rotations, converges too slowly for a test: see the README.)
    mesh, sim, tip = guided_cantilever("corotational")
    target = sim.positions.copy()
    target[tip, 2] += 1.5
    result = sim.solve_static(load_steps=6, tolerance=1e-8, prescribed=target)
    assert len(result["residual_history"]) == 6
    assert all(h[-1] <= 1e-8 for h in result["residual_history"])
    np.testing.assert_allclose(sim.positions[tip], target[tip], rtol=0, atol=1e-12)
    mid = mesh.nodes_on_plane("x", 5.0)
    assert sim.displacements[mid, 2].mean() == pytest.approx(0.75, abs=0.01)
    assert np.abs(sim.velocities).max() == 0.0


def test_prescribed_positions_are_checked():
    _mesh, sim, tip = guided_cantilever("linear")
    with pytest.raises(ValueError, match="prescribed must have shape"):
        sim.solve_static(prescribed=np.zeros((3, 3)))
    bad = sim.positions.copy()
    bad[tip[0]] = np.nan
    with pytest.raises(ValueError, match="prescribed positions must be finite"):
        sim.solve_static(prescribed=bad)
