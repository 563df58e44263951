"""to_exudyn / exudyn_fem: a corotate body and its Craig-Bampton basis handed to Exudyn as
ObjectFFRFreducedOrder (skipped without exudyn, the [mbs] extra).

A Hex20 cantilever 1 x 0.1 x 0.1 m (4 x 1 x 1 cells), its root face fixed in the basis (so it
defines the floating frame), four normal modes and the constraint modes of a tip node.

* The inertia invariants Exudyn computes from corotate's consistent mass are the box's exact
  ones (the consistent mass integrates the quadratic position field exactly): mass rho V,
  centre of mass at the box's centre, the inertia tensor about the mesh's origin. The reduced
  mass and stiffness are I and diag(omega^2) (the basis is orthonormalised).
* Held at its root by a joint on the root nodes, the body under a tip load in Exudyn's static
  solver deflects exactly as corotate's reduced model: Phi diag(1/omega^2) Phi^T f (the
  constraint modes make that the full linear answer too).
* A stiff body on a revolute joint, released horizontal, reaches the bottom when the exact
  rigid compound pendulum does.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from scipy.special import ellipk

import corotate as cr
from corotate.modal import ModalBasis, craig_bampton, exudyn_fem, to_exudyn

exu = pytest.importorskip("exudyn")
items = pytest.importorskip("exudyn.itemInterface")

L, B, H, RHO = 1.0, 0.1, 0.1, 1000.0


@pytest.fixture(scope="module")
def reduced():
    mesh = cr.beam(L, B, H, cells=(4, 1, 1), element="hex20")
    body = cr.Body(mesh, cr.Material(E=2e9, nu=0.3, density=RHO), model="linear")
    root = mesh.nodes_on_plane("x", 0.0)
    tip = mesh.nearest_node((L, B, H))
    basis = craig_bampton(body, root, n_modes=4, interface_nodes=[tip])
    return mesh, body, basis, root, tip


def _quiet_settings(end_time: float = 0.0, steps: int = 1):
    s = exu.SimulationSettings()
    s.solution.file.write = False
    s.staticSolver.verboseMode = 0
    s.timeIntegration.verboseMode = 0
    s.staticSolver.newton.relativeTolerance = 1e-12
    s.timeIntegration.endTime = end_time
    s.timeIntegration.numberOfSteps = steps
    return s


def test_the_inertia_invariants_are_the_box_s(reduced):
    _mesh, body, basis, *_ = reduced
    cms = to_exudyn(exu.SystemContainer().AddSystem(), body, basis).interface
    m = RHO * L * B * H
    assert cms.totalMass == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(cms.chiU, [L / 2, B / 2, H / 2], rtol=1e-12)
    # The box [0, L] x [0, B] x [0, H] about its corner: I_xx = m (B^2 + H^2) / 3, I_xy = -m L B / 4, ...
    expected = m * np.array(
        [
            [(B**2 + H**2) / 3, -L * B / 4, -L * H / 4],
            [-L * B / 4, (L**2 + H**2) / 3, -B * H / 4],
            [-L * H / 4, -B * H / 4, (L**2 + B**2) / 3],
        ]
    )
    np.testing.assert_allclose(cms.inertiaLocal, expected, rtol=1e-12, atol=1e-14 * m)
    np.testing.assert_allclose(cms.massMatrixReduced, np.eye(basis.size), atol=1e-12)
    np.testing.assert_allclose(
        cms.stiffnessMatrixReduced, np.diag(basis.eigenvalues), atol=1e-12 * basis.eigenvalues.max()
    )


def test_the_fem_interface_holds_corotate_s_arrays(reduced):
    mesh, body, basis, *_ = reduced
    fem = exudyn_fem(body, basis)
    np.testing.assert_array_equal(fem.GetNodePositionsAsArray(), mesh.points)
    np.testing.assert_array_equal(fem.modeBasis["matrix"], basis.vectors)
    assert (fem.GetMassMatrix() != body.mass_matrix()).nnz == 0
    assert (fem.GetStiffnessMatrix() != body.stiffness_matrix()).nnz == 0
    np.testing.assert_allclose(fem.GetEigenFrequenciesHz(), basis.frequencies, rtol=1e-15)
    assert len(fem.GetSurfaceTriangles()) == 2 * (4 * 4 + 2)  # 16 side and 2 end quads, two triangles each


def test_a_held_body_deflects_statically_as_the_reduced_model(reduced):
    mesh, body, basis, root, tip = reduced
    mbs = exu.SystemContainer().AddSystem()
    flexible = to_exudyn(mbs, body, basis)
    ground = mbs.AddObject(items.ObjectGround())
    at_root = mbs.AddMarker(items.MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, B / 2, H / 2]))
    mbs.AddObject(items.GenericJoint(markerNumbers=[at_root, flexible.rigid_marker(root)], constrainedAxes=[1] * 6))
    load = np.array([30.0, -200.0, -1000.0])
    mbs.AddLoad(items.LoadForceVector(markerNumber=flexible.position_marker([tip]), loadVector=load.tolist()))
    mbs.Assemble()
    np.testing.assert_allclose(flexible.positions(), mesh.points, atol=1e-15)
    mbs.SolveStatic(_quiet_settings())
    f = np.zeros(3 * mesh.n_nodes)
    f[3 * tip : 3 * tip + 3] = load
    u = (basis.vectors @ ((basis.vectors.T @ f) / basis.eigenvalues)).reshape(-1, 3)
    assert np.abs(u).max() > 1e-4
    np.testing.assert_allclose(flexible.positions() - mesh.points, u, atol=1e-10 * np.abs(u).max())
    np.testing.assert_allclose(flexible.positions([tip]), mesh.points[[tip]] + u[[tip]], atol=1e-10 * np.abs(u).max())


def test_the_frame_is_placed_where_asked(reduced):
    mesh, body, basis, *_ = reduced
    mbs = exu.SystemContainer().AddSystem()
    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    flexible = to_exudyn(mbs, body, basis, position=(1.0, 2.0, 3.0), rotation=R)
    mbs.Assemble()
    np.testing.assert_allclose(flexible.positions(), (1.0, 2.0, 3.0) + mesh.points @ R.T, atol=1e-14)


def test_a_stiff_pendulum_reaches_the_bottom_when_the_rigid_one_does(reduced):
    # The compound pendulum released horizontal: a quarter period T/4 = sqrt(I / (m g d)) K(1/sqrt(2))
    # (K the complete elliptic integral of the first kind, parameter m = 1/2), I about the axis
    # through (0, y, H/2), d = the centre of mass's distance from it.
    mesh, body, basis, root, _tip = reduced
    g = 9.81
    mbs = exu.SystemContainer().AddSystem()
    flexible = to_exudyn(mbs, body, basis, gravity=(0.0, 0.0, -g))
    ground = mbs.AddObject(items.ObjectGround())
    hinge = mbs.AddMarker(items.MarkerBodyRigid(bodyNumber=ground, localPosition=[0.0, B / 2, H / 2]))
    mbs.AddObject(
        items.GenericJoint(markerNumbers=[hinge, flexible.rigid_marker(root)], constrainedAxes=[1, 1, 1, 1, 0, 1])
    )
    m = RHO * L * B * H
    inertia = m * (L**2 + H**2) / 3 - m * (H / 2) ** 2  # about the corner edge, shifted to z = H/2
    quarter = np.sqrt(inertia / (m * g * L / 2)) * ellipk(0.5)
    end, steps = 0.5, 500
    sensor = mbs.AddSensor(
        items.SensorMarker(
            markerNumber=flexible.position_marker(mesh.nodes_on_plane("x", L)),
            outputVariableType=exu.OutputVariableType.Position,
            storeInternal=True,
        )
    )
    mbs.Assemble()
    settings = _quiet_settings(end, steps)
    settings.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    settings.solution.sensors.writePeriod = end / steps
    mbs.SolveDynamic(settings)
    tip = mbs.GetSensorStoredData(sensor)
    # The time the tip passes x = 0 (straight down), interpolated between samples.
    k = int(np.flatnonzero(tip[:, 1] < 0)[0])
    t0, t1, x0, x1 = tip[k - 1, 0], tip[k, 0], tip[k - 1, 1], tip[k, 1]
    t_bottom = t0 + (t1 - t0) * x0 / (x0 - x1)
    # Bending (the first frequency is ~20x the pendulum's) and the time step (h / T ~ 1e-3)
    # move it by little: measured 1.4e-5.
    assert t_bottom == pytest.approx(quarter, rel=1e-4)


def test_bad_input_is_refused(reduced):
    mesh, body, basis, root, _tip = reduced
    mbs = exu.SystemContainer().AddSystem()
    other = cr.Body(cr.beam(L, B, H, cells=(2, 1, 1), element="hex20"), cr.Material(E=2e9, nu=0.3, density=RHO))
    with pytest.raises(ValueError, match="not built on this body's mesh"):
        to_exudyn(mbs, other, basis)
    rigid = ModalBasis(
        vectors=np.column_stack([np.tile([0.0, 0.0, 1.0], mesh.n_nodes), basis.vectors[:, 0]]),
        eigenvalues=[0.0, basis.eigenvalues[0]],
        rest_positions=mesh.points,
        fixed_dofs=[],
        interface_nodes=[],
        n_normal_modes=2,
    )
    with pytest.raises(ValueError, match="the basis holds a rigid-body motion"):
        exudyn_fem(body, rigid)
    with pytest.raises(TypeError, match="ModalBasis"):
        exudyn_fem(body, basis.vectors)
    with pytest.raises(ValueError, match="rotation"):
        to_exudyn(mbs, body, basis, rotation=2 * np.eye(3))
    with pytest.raises(ValueError, match="gravity"):
        to_exudyn(mbs, body, basis, gravity=(0.0, np.nan, 0.0))
    flexible = to_exudyn(mbs, body, basis)
    with pytest.raises(ValueError, match="not all on one line"):
        flexible.rigid_marker(root[:2])
    line = [i for i in root if np.isclose(mesh.points[i, 2], 0.0) and np.isclose(mesh.points[i, 1], 0.0)]
    line += [i for i in range(mesh.n_nodes) if np.allclose(mesh.points[i, 1:], 0.0) and mesh.points[i, 0] > 0]
    with pytest.raises(ValueError, match="not all on one line"):
        flexible.rigid_marker(line)
    with pytest.raises(ValueError, match="out of range"):
        flexible.position_marker([mesh.n_nodes])


def test_without_exudyn_the_error_names_the_extra(reduced, monkeypatch):
    _mesh, body, basis, *_ = reduced
    monkeypatch.setitem(sys.modules, "exudyn", None)
    with pytest.raises(ImportError, match=r"corotate-fem\[mbs\]"):
        exudyn_fem(body, basis)
