"""Shared scenes of the contact tests."""

import numpy as np

import corotate as cr

CUBE = 0.1  # [m] edge of the test cube
CELLS = 4  # cells per edge: the element size is CUBE / CELLS


def cube(z0: float = 0.0, E: float = 1e5, cells: int = CELLS, **simulation):
    """A soft 0.1 m cube (1 kg) whose bottom face is at height z0, under gravity."""
    mesh = cr.box((CUBE, CUBE, CUBE), (cells, cells, cells), origin=(-CUBE / 2, -CUBE / 2, z0))
    body = cr.Body(mesh, cr.Material(E=E, nu=0.3, density=1000.0))
    return mesh, cr.Simulation(body, gravity=(0.0, 0.0, -9.81), **simulation)


def bottom_nodes(mesh):
    return np.flatnonzero(np.isclose(mesh.points[:, 2], mesh.points[:, 2].min()))
