"""The API surprises of issue 28, each by name: a Body's mesh is its own, fix replaces while
also_fix adds, a bool is not a number, cheap state queries are properties, a ModalBasis and
a ModalBody file are checked with messages in the user's terms, on_unstable="allow" says
so once, and a failed call leaves the state as an untouched twin's."""

import warnings

import numpy as np
import pytest

import corotate as cr
from corotate.modal import ModalBody, craig_bampton
from corotate.modal.reduction import ModalBasis


def beam_sim(**kwargs) -> cr.Simulation:
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    sim = cr.Simulation(cr.Body(mesh, cr.Material(E=1e6, nu=0.3, density=1000)), dt=0.01, **kwargs)
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    return sim


# -- a Body owns read-only copies of its mesh ----------------------------------------------------


def test_changing_the_mesh_after_building_the_body_moves_nothing():
    mesh = cr.beam(2.0, 0.5, 0.5, cells=(8, 2, 2))
    body = cr.Body(mesh, cr.Material())
    sim = cr.Simulation(body, dt=0.01)
    rest = mesh.points.copy()
    mesh.points[:, 2] += 100  # the caller's mesh, not the body's
    assert np.array_equal(sim.displacements, np.zeros_like(rest))
    assert np.array_equal(body.mesh.points, rest)
    assert body.energy(rest) == 0.0


def test_the_bodys_mesh_arrays_are_read_only():
    body = cr.Body(cr.box(), cr.Material())
    with pytest.raises(ValueError, match="read-only"):
        body.mesh.points[:, 2] += 1
    with pytest.raises(ValueError, match="read-only"):
        body.mesh.cells[0, 0] = 1


# -- fix replaces, also_fix adds ---------------------------------------------------------------


def test_fix_replaces_the_set_and_also_fix_adds_to_it():
    sim = beam_sim()
    clamp = sim.body.mesh.nodes_on_plane("x", 0.0)
    tip = int(sim.body.mesh.nearest_node((2.0, 0.5, 0.5)))
    sim.also_fix([tip])
    assert sim.fixed_nodes.tolist() == sorted([*clamp.tolist(), tip])
    sim.also_fix(clamp[:2])  # already fixed: no duplicates
    assert sim.fixed_nodes.tolist() == sorted([*clamp.tolist(), tip])
    sim.fix([tip])  # replaces: the clamp is released
    assert sim.fixed_nodes.tolist() == [tip]
    with pytest.raises(AttributeError, match=r"also_fix\(nodes\) \(adds to it\)"):
        sim.fixed_nodes = [1]


# -- types: a bool is not a number -----------------------------------------------------------------


@pytest.mark.parametrize("bad", [True, np.bool_(False), "1e6", [1e6]])  # (E=None: the default, 1e6 Pa)
def test_material_parameters_must_be_real_numbers(bad):
    with pytest.raises(TypeError, match=r"Material E must be a real number"):
        cr.Material(E=bad)


def test_material_takes_numpy_scalars():
    m = cr.Material(E=np.float32(2e6), nu=np.float64(0.25), density=np.int64(900))
    assert (m.E, m.nu, m.density) == (2e6, 0.25, 900)
    assert cr.Material(E=np.array(3e6)).lame[1] == pytest.approx(3e6 / 2 / 1.3)


# -- cheap state queries are properties ------------------------------------------------------------


def test_kinetic_and_elastic_energy_are_properties():
    sim = beam_sim(gravity=(0, 0, -9.81))
    sim.step(3)
    v = sim.velocities.ravel()
    expected = 0.5 * v @ (sim.mass_matrix() @ v)
    assert sim.kinetic_energy == pytest.approx(expected, rel=1e-12)
    assert sim.energy == pytest.approx(sim.body.energy(sim.positions), rel=1e-12)
    with pytest.warns(DeprecationWarning, match="kinetic_energy is a property now"):
        assert sim.kinetic_energy() == float(sim.kinetic_energy)
    with pytest.warns(DeprecationWarning, match="energy is a property now"):
        assert sim.energy() == float(sim.energy)


# -- ModalBasis and ModalBody files --------------------------------------------------------------


@pytest.fixture(scope="module")
def modal_body():
    mesh = cr.beam(1.0, 0.2, 0.2, cells=(5, 1, 1))
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000))
    return ModalBody(craig_bampton(body, mesh.nodes_on_plane("x", 0.0), n_modes=4), dt=0.01)


def basis_fields(basis: ModalBasis) -> dict:
    return dict(
        vectors=basis.vectors,
        eigenvalues=basis.eigenvalues,
        rest_positions=basis.rest_positions,
        fixed_dofs=basis.fixed_dofs,
        interface_nodes=basis.interface_nodes,
        n_normal_modes=basis.n_normal_modes,
    )


def test_a_nan_in_the_basis_vectors_is_named_at_construction(modal_body):
    fields = basis_fields(modal_body.basis)
    vectors = fields["vectors"].copy()
    vectors[40, 2] = np.nan
    with pytest.raises(ValueError, match=r"ModalBasis vectors holds nan at \[40, 2\] \(1 non-finite value\(s\)\)"):
        ModalBasis(**{**fields, "vectors": vectors})


def test_one_dimensional_vectors_are_a_shape_error_not_an_index_error(modal_body):
    fields = basis_fields(modal_body.basis)
    with pytest.raises(ValueError, match=r"vectors must have shape \(3n, r\) = \(72, r\)"):
        ModalBasis(**{**fields, "vectors": fields["vectors"][:, 0]})


def test_rest_positions_that_do_not_fit_the_vectors_are_named(modal_body):
    fields = basis_fields(modal_body.basis)
    with pytest.raises(ValueError, match=r"vectors must have shape \(3n, r\) = \(6, r\)"):
        ModalBasis(**{**fields, "rest_positions": fields["rest_positions"][:2]})


def test_interface_nodes_out_of_range_are_named(modal_body):
    fields = basis_fields(modal_body.basis)
    with pytest.raises(ValueError, match=r"interface_nodes: node 72 is out of range \[0, 24\)"):
        ModalBasis(**{**fields, "interface_nodes": np.array([3, 72])})
    with pytest.raises(ValueError, match=r"eigenvalues must have shape \(4,\)"):
        ModalBasis(**{**fields, "eigenvalues": fields["eigenvalues"][:3]})


def test_loading_random_bytes_says_it_is_not_a_modal_body_file(tmp_path):
    f = tmp_path / "noise.npz"
    f.write_bytes(np.random.default_rng(1).bytes(300))
    with pytest.raises(ValueError, match=r"noise\.npz is not a corotate modal body file: .*\.npz \(zip\) archive"):
        ModalBody.load(f)


def test_loading_a_truncated_file_says_it_is_truncated(tmp_path, modal_body):
    f = tmp_path / "body.npz"
    modal_body.save(f)
    data = f.read_bytes()
    f.write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match=r"body\.npz is truncated or corrupt"):
        ModalBody.load(f)
    with pytest.raises(FileNotFoundError, match=r"missing\.npz"):
        ModalBody.load(tmp_path / "missing.npz")
    modal_body.save(f)
    assert ModalBody.load(f).n_modes == modal_body.n_modes


# -- on_unstable="allow" warns once ------------------------------------------------------------------


def test_allowing_an_unstable_step_warns_once():
    mesh = cr.box((1.0, 0.2, 0.2), (5, 1, 1))
    body = cr.Body(mesh, cr.Material(E=1e6, density=1000))
    probe = cr.ExplicitSimulation(body)
    dt = 9.7 * probe.critical_time_step
    sim = cr.ExplicitSimulation(body, dt=dt, on_unstable="allow")
    with pytest.warns(cr.SimulationWarning, match=r"9\.7 times the critical step .*'allow' takes it anyway"):
        sim.step(1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sim.step(1)  # once per simulation
    stable = cr.ExplicitSimulation(body, dt=0.5 * probe.critical_time_step, on_unstable="allow")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        stable.step(2)  # below the limit: nothing to say


# -- a failed call restores the state an untouched twin has --------------------------------------


def stop_at_two(done, n):
    if done == 2:
        raise KeyError("stop")


def failed_call_and_twin(solver, matrix_reuse_angle: float = 0.0) -> tuple[cr.Simulation, cr.Simulation]:
    """Two equal simulations after 3 + 4 steps, the first with a call between them whose
    progress callback raised after 2 of its 5 steps (the state restored). Every step assembles
    its matrix unless matrix_reuse_angle is given: a kept matrix is not part of the state."""
    a, b = (beam_sim(gravity=(0, 0, -9.81), solver=solver, matrix_reuse_angle=matrix_reuse_angle) for _ in range(2))
    a.step(3)
    b.step(3)
    with pytest.raises(KeyError):
        a.step(5, stop_at_two)
    assert np.array_equal(a.positions, b.positions) and a.time == b.time
    a.step(4)
    b.step(4)
    return a, b


@pytest.mark.parametrize("solver", [cr.Direct(), cr.PCG(preconditioner="block_jacobi")])
def test_a_raising_progress_callback_leaves_the_state_of_an_untouched_twin(solver):
    a, b = failed_call_and_twin(solver)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)


def test_a_raising_progress_callback_drops_a_kept_matrix():
    """The failed call's steps may have assembled a new matrix: the step after the restore
    assembles afresh where the twin keeps its own, and the two differ by that lag only."""
    a, b = failed_call_and_twin(cr.PCG(), matrix_reuse_angle=0.05)
    assert b.stats["kept_matrix_steps"] == 5 and a.stats["kept_matrix_steps"] == 4
    sag = np.abs(b.displacements).max()
    assert 0 < np.abs(a.positions - b.positions).max() < 1e-3 * sag


@pytest.mark.parametrize("preconditioner", ["reference_factor", "two_level", "auto"])
def test_a_raising_progress_callback_restores_the_rotating_preconditioners_too(preconditioner):
    a, b = failed_call_and_twin(cr.PCG(preconditioner=preconditioner, warm_start=False))
    assert np.array_equal(a.positions, b.positions)


@pytest.mark.parametrize("bad", [True, "0.01"])
def test_time_steps_must_be_real_numbers(bad):
    body = cr.Body(cr.box(), cr.Material())
    with pytest.raises(TypeError, match=r"dt must be a real number, got"):
        cr.Simulation(body, dt=bad)
    with pytest.raises(TypeError, match=r"time step dt must be a real number, got"):
        cr.ExplicitSimulation(body, dt=bad)
    sim = cr.Simulation(body, dt=0.01)
    with pytest.raises(TypeError, match=r"dt must be a real number"):
        sim.dt = bad
    assert sim.dt == 0.01
