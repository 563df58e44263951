"""Contact springs reach the linear solve's preconditioner: the default PCG on a body large
enough for its two-level preconditioner, lying on the floor between two walls, converges in
as few iterations as the same body clamped without contact. The two-level coarse level once
left the springs out, and its coarse correction pushed whole regions into the floor: 20
capped iterations per step that left 10-45 % of the residual (42 per step on average over a
run, impacts included). The C++ tests check the preconditioner itself
(tests/cpp/test_solvers.cpp, two_level_*contact*)."""

import corotate as cr


def test_a_beam_between_walls_solves_like_the_clamped_beam():
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(40, 8, 8))  # 15,360 tets, 9,963 unknowns: two-level
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000.0))
    lying = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81))
    for wall in (cr.Plane((0, 0, 0), (0, 0, 1)), cr.Plane((0, 0, 0), (0, 1, 0)), cr.Plane((0, 1, 0), (0, -1, 0))):
        lying.add_obstacle(wall, friction=0.3)
    lying.step(30)  # landed and settled against the walls
    lying.reset_stats()
    lying.step(20)
    stats = lying.stats
    assert len(lying.contacts["nodes"]) > 900
    assert stats["stalled_steps"] == 0
    # measured 3.5 (the clamped beam without contact: 1.9); 20 and more before
    assert stats["iterations_per_step"] <= 5
    assert lying.positions[:, 2].min() > -1e-4 * 1.0 / 8  # resting on the floor, not in it
