"""corotate: fast simulation of large deformations of elastic solids.

Co-rotational, linear and hyperelastic FEM on linear and quadratic tet and hex meshes, stepped implicitly
frame by frame from Python by a C++ core; mass-spring bodies (cloth, cube lattices, any
tet/hex mesh) stepped explicitly with a safe time step (MassSpringBody, ExplicitSimulation).

    import corotate as cr
    mesh = cr.beam(5.0, 1.0, 1.0, cells=(20, 4, 4))
    body = cr.Body(mesh, cr.Material(E=1e7, nu=0.3, density=1000))
    sim = cr.Simulation(body, dt=0.01, gravity=(0, 0, -9.81))
    sim.fix(mesh.nodes_on_plane("x", 0.0))
    sim.step(5)
"""

from __future__ import annotations

from . import _wait_policy  # noqa: F401  (first: OpenMP reads its wait policy as the core loads)

# isort: split
import corotate._core as _core

from .body import Body
from .build import build_info
from .driven_body import SimulationWarning
from .embedding import EmbeddedSurface, read_surface
from .explicit import ExplicitSimulation
from .feedback import HapticFeedback, ToolFeedback
from .joined_body import JoinedBody
from .mass_spring import MassSpringBody, SpringGeometry
from .material import Material
from .mesh import SUPPORTED_CELL_TYPES, Mesh, beam, box, cell_types, read_mesh, rectangle, write_mesh
from .meshing import tetrahedralize
from .obstacles import Box, Capsule, Cylinder, Plane, Sphere, TriangleMesh
from .output import TimeSeriesWriter
from .scene import Scene
from .simulation import Simulation
from .solvers import PCG, Direct
from .surfaces import boundary_surface, loop_subdivide, sphere_surface, split_at_centroids
from .sweep import ParameterTable, open_sweep, run_sweep  # imports no Dask until a sweep runs
from .threads import available_threads, have_openmp, set_threads, threads

__all__ = [
    "Mesh",
    "cell_types",
    "SUPPORTED_CELL_TYPES",
    "beam",
    "box",
    "rectangle",
    "read_mesh",
    "write_mesh",
    "TimeSeriesWriter",
    "Material",
    "Body",
    "PCG",
    "Direct",
    "Simulation",
    "Scene",
    "JoinedBody",
    "MassSpringBody",
    "SpringGeometry",
    "ExplicitSimulation",
    "HapticFeedback",
    "ToolFeedback",
    "Plane",
    "Sphere",
    "Box",
    "Capsule",
    "Cylinder",
    "TriangleMesh",
    "SimulationWarning",
    "EmbeddedSurface",
    "read_surface",
    "boundary_surface",
    "loop_subdivide",
    "split_at_centroids",
    "sphere_surface",
    "tetrahedralize",
    "set_threads",
    "threads",
    "available_threads",
    "have_openmp",
    "build_info",
    "ParameterTable",
    "run_sweep",
    "open_sweep",
]
__version__: str = _core.__version__  # from the VERSION file, through CMake
