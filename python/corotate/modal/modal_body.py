"""A reduced (modal) flexible body stepped frame by frame, like Simulation.

The state is the modal coordinates q (r of them, r ~ 10-50); the C++ core steps them
implicitly (modal_integrator.hpp), so a step costs microseconds however large the mesh was.
Nodal loads are projected onto the basis (only the loaded nodes' rows are read); nodal
displacements u = Phi q are recovered on request, for all nodes or a subset, into arrays
the caller may preallocate (``out=``), so a frame loop allocates nothing.

Internal forces, in modal coordinates (see cpp/include/corotate/modal/modal_forces.hpp):

    f(q) = -(K q + 1/2 sum_i q_i A_i q + 1/3 sum_ij q_i q_j B_ij q)

K = diag(omega^2) for the orthonormalised basis (plus the load-based geometric stiffness
when load cases carry one), A the mode-based geometric stiffness (paper eqs 9-11) or the
quadratic StVK term, B the cubic StVK term (Barbic & James 2005).
"""

from __future__ import annotations

import functools
import os
import threading
import zipfile
import zlib
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, ClassVar, TypeVar

import numpy as np

import corotate._core as _core

from .._attributes import SettableOnly
from ..mesh import Mesh
from .partial_rotation import PartialRotation
from .reduction import ModalBasis

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..output import TimeSeriesWriter

__all__ = ["ModalBody"]

_FORMAT_VERSION = 1

_F = TypeVar("_F", bound=Callable[..., Any])


def _one_at_a_time(method: _F) -> _F:
    """step() and displacements() release the GIL while the core works; a second thread that
    steps, recovers or changes the state of the same body meanwhile gets RuntimeError instead
    of racing it (the same rule as Simulation's "the simulation is busy")."""

    @functools.wraps(method)
    def guarded(self: ModalBody, *args: Any, **kwargs: Any) -> Any:
        if not self._busy.acquire(blocking=False):
            raise RuntimeError(
                f"the modal body is busy: {method.__name__}() was called while another thread steps it or "
                "recovers its displacements; use one thread per body, or wait for that call to return"
            )
        try:
            return method(self, *args, **kwargs)
        finally:
            self._busy.release()

    return guarded  # type: ignore[return-value]


def _tensor(value: ArrayLike | None, shape: tuple[int, int], what: str) -> np.ndarray:
    if value is None:
        return np.zeros((0, 0))
    t = np.asarray(value, dtype=np.float64)
    if t.size != shape[0] * shape[1]:
        raise ValueError(
            f"{what} must have {shape[0] * shape[1]} entries (r = {round(shape[1] ** 0.5)}), got shape {t.shape}"
        )
    return np.asfortranarray(t.reshape(shape, order="F"))


class ModalBody(SettableOnly):
    """A flexible body reduced to a modal basis.

    basis       ModalBasis (craig_bampton); its vectors must be M-orthonormal
    dt          time step [s] of step()
    rayleigh    (alpha [1/s], beta [s]): damping C = alpha I + beta K in modal coordinates
    quadratic   optional (r, r, r) tensor A[l, k, i] = (A_i)_lk of the quadratic force term
                (mode-based geometric stiffness, or reduced StVK)
    cubic       optional (r, r, r, r) tensor B[l, k, i, j] = (B_ij)_lk of the cubic term
    mesh        optional Mesh for ParaView output (connectivity only; not needed to step)
    recovery    "float64" (default, exact) or "float32": recover displacements from a
                single-precision copy of the basis (half the memory traffic of recovering
                every node, which is bandwidth-bound; relative error ~1e-7)
    partial_rotation  optional PartialRotation (the paper's §3.2) built on the basis's rest
                positions: recovered displacements are turned domain by domain, in the C++
                core, without allocating (settable; saved with the body)

    State: ``q``, ``modal_velocities``, ``modal_forces`` are (r,) writable views of the
    core's state; ``time`` [s]. Bad input raises ValueError and leaves the state as it was.

    Threads: one call at a time per body; a call that steps, recovers or changes the state
    while another thread's step() or displacements() runs raises RuntimeError. The views
    (q, ...) cannot be guarded: do not write into them while another thread steps.
    """

    _READ_ONLY_HINTS: ClassVar[dict[str, str]] = {
        "basis": "a ModalBody is built for one basis; create a new one",
        "q": "write into the view instead, e.g. body.q[:] = values",
        "modal_velocities": "write into the view instead",
        "modal_forces": "write into the view or use apply_forces(nodes, forces)",
        "time": "it advances with step(); reset() goes back to t = 0",
        "mesh": "pass mesh= when creating the ModalBody",
        "recovery": "pass recovery= when creating the ModalBody",
    }

    def __init__(
        self,
        basis: ModalBasis,
        dt: float = 0.01,
        rayleigh: tuple[float, float] = (0.0, 0.0),
        quadratic: ArrayLike | None = None,
        cubic: ArrayLike | None = None,
        mesh: Mesh | None = None,
        recovery: str = "float64",
        partial_rotation: PartialRotation | None = None,
    ) -> None:
        if not isinstance(basis, ModalBasis):
            raise TypeError("basis must be a corotate.modal.ModalBasis (see craig_bampton)")
        if mesh is not None and (not isinstance(mesh, Mesh) or mesh.points.shape != basis.rest_positions.shape):
            raise ValueError("mesh must be a corotate.Mesh with the basis's nodes")
        if recovery not in ("float64", "float32"):
            raise ValueError(f"recovery must be 'float64' or 'float32', got {recovery!r}")
        r = basis.size
        self._busy = threading.Lock()
        alpha, beta = (float(v) for v in rayleigh)
        self._recovery = recovery
        self._recovery_vectors = basis.vectors if recovery == "float64" else basis.vectors.astype(np.float32)
        self._basis = basis
        self._mesh = mesh
        self._quadratic = _tensor(quadratic, (r * r, r), "quadratic")
        self._cubic = _tensor(cubic, (r * r, r * r), "cubic")
        self._core = _core.ModalIntegrator(
            np.diag(basis.eigenvalues), self._quadratic, self._cubic, float(dt), alpha, beta
        )
        self._load_cases: np.ndarray = np.zeros((0, r))
        self._load_stiffness: np.ndarray = np.zeros((0, r, r))
        self._amplitudes: np.ndarray = np.zeros(0)
        self._partial_rotation: PartialRotation | None = None
        self.partial_rotation = partial_rotation

    # -- state ---------------------------------------------------------------

    @property
    def basis(self) -> ModalBasis:
        return self._basis

    @property
    def mesh(self) -> Mesh | None:
        return self._mesh

    @property
    def recovery(self) -> str:
        """The recovery precision, "float64" or "float32" (read-only)."""
        return self._recovery

    @property
    def partial_rotation(self) -> PartialRotation | None:
        """The PartialRotation applied while recovering displacements, or None (settable)."""
        return self._partial_rotation

    @partial_rotation.setter
    @_one_at_a_time
    def partial_rotation(self, value: PartialRotation | None) -> None:
        if value is not None and (not isinstance(value, PartialRotation) or value.n_nodes != self.n_nodes):
            raise ValueError(f"partial_rotation must be a PartialRotation on this body's {self.n_nodes} nodes, or None")
        self._partial_rotation = value

    @property
    def n_modes(self) -> int:
        """Number of modal coordinates r."""
        return self._basis.size

    @property
    def n_nodes(self) -> int:
        return int(self._basis.rest_positions.shape[0])

    @property
    def q(self) -> np.ndarray:
        """(r,) modal coordinates (a writable view)."""
        return self._core.q

    @property
    def modal_velocities(self) -> np.ndarray:
        """(r,) modal velocities dq/dt (a writable view)."""
        return self._core.v

    @property
    def modal_forces(self) -> np.ndarray:
        """(r,) external modal forces Phi^T f_ext (a writable view)."""
        return self._core.p

    @property
    def time(self) -> float:
        return float(self._core.time)

    @property
    def dt(self) -> float:
        """Time step [s] (settable)."""
        return float(self._core.settings[0])

    @dt.setter
    @_one_at_a_time
    def dt(self, value: float) -> None:
        _, a, b = self._core.settings
        self._core.settings = (float(value), a, b)

    @property
    def rayleigh(self) -> tuple[float, float]:
        """(alpha [1/s], beta [s]) damping (settable)."""
        _, a, b = self._core.settings
        return float(a), float(b)

    @rayleigh.setter
    @_one_at_a_time
    def rayleigh(self, value: tuple[float, float]) -> None:
        alpha, beta = (float(v) for v in value)
        self._core.settings = (self.dt, alpha, beta)

    @property
    def stiffness(self) -> np.ndarray:
        """(r, r) modal stiffness at q = 0 with the current load stiffness (a new array)."""
        return np.asarray(self._core.stiffness)

    @_one_at_a_time
    def set_state(self, q: ArrayLike | None = None, velocities: ArrayLike | None = None) -> None:
        """Set modal coordinates and/or velocities ((r,) finite; checked, state kept on error)."""
        q_new = None if q is None else np.asarray(q, dtype=np.float64)
        v_new = None if velocities is None else np.asarray(velocities, dtype=np.float64)
        for value, what in ((q_new, "q"), (v_new, "velocities")):
            if value is not None and (value.shape != (self.n_modes,) or not np.all(np.isfinite(value))):
                raise ValueError(f"{what} must be a finite array of shape ({self.n_modes},)")
        if q_new is not None:
            self._core.set_q(q_new)
        if v_new is not None:
            self._core.set_v(v_new)

    # -- loads ---------------------------------------------------------------

    @_one_at_a_time
    def apply_forces(self, nodes: ArrayLike, forces: ArrayLike) -> None:
        """Set the external modal forces to Phi^T f for nodal forces ``forces`` ((k, 3) or
        (3,) for all the nodes) on ``nodes`` (k,); replaces the previous modal forces (and
        load-case amplitudes). Reads only the loaded nodes' rows of the basis."""
        idx = np.atleast_1d(np.asarray(nodes))
        if idx.ndim != 1 or (idx.size and not np.issubdtype(idx.dtype, np.integer)):
            raise ValueError("nodes must be a 1-D array of integer node indices")
        f = np.asarray(forces, dtype=np.float64)
        if f.shape == (3,):
            f = np.broadcast_to(f, (idx.size, 3))
        if f.shape != (idx.size, 3):
            raise ValueError(f"forces must have shape ({idx.size}, 3) or (3,), got {f.shape}")
        p = np.empty(self.n_modes)
        _core.project_nodal_forces(self._basis.vectors, idx.astype(np.int64), np.ascontiguousarray(f), p)
        self._core.set_p(p)
        self._set_amplitudes(np.zeros(len(self._amplitudes)), update_forces=False)

    @_one_at_a_time
    def set_load_cases(self, modal_loads: ArrayLike, geometric_stiffness: ArrayLike | None = None) -> None:
        """Unit load cases: (k, r) modal forces of each (Phi^T P_i) and optionally their (k, r, r)
        modal geometric stiffness (load_based_geometric_stiffness). ``load_amplitudes`` then
        sets p = sum F_i Phi^T P_i and K = K0 + sum F_i K_sigma0^i (the paper's eqs 7-8)."""
        loads = np.array(modal_loads, dtype=np.float64, ndmin=2)
        k = loads.shape[0]
        if loads.shape != (k, self.n_modes) or not np.all(np.isfinite(loads)):
            raise ValueError(f"modal_loads must be a finite (k, {self.n_modes}) array")
        if geometric_stiffness is None:
            geo = np.zeros((k, self.n_modes, self.n_modes))
        else:
            geo = np.array(geometric_stiffness, dtype=np.float64)
            if geo.shape != (k, self.n_modes, self.n_modes) or not np.all(np.isfinite(geo)):
                raise ValueError(f"geometric_stiffness must be a finite ({k}, {self.n_modes}, {self.n_modes}) array")
        self._load_cases, self._load_stiffness = loads, geo
        self._set_amplitudes(np.zeros(k))

    @property
    def load_amplitudes(self) -> np.ndarray:
        """(k,) current amplitudes F_i of the load cases (settable; a copy)."""
        return self._amplitudes.copy()

    @load_amplitudes.setter
    @_one_at_a_time
    def load_amplitudes(self, value: ArrayLike) -> None:
        F = np.atleast_1d(np.asarray(value, dtype=np.float64))
        if F.shape != self._amplitudes.shape or not np.all(np.isfinite(F)):
            raise ValueError(f"load_amplitudes must be a finite array of shape {self._amplitudes.shape}")
        self._set_amplitudes(F)

    def _set_amplitudes(self, F: np.ndarray, update_forces: bool = True) -> None:
        extra = np.tensordot(F, self._load_stiffness, axes=1) if F.size else np.zeros((self.n_modes,) * 2)
        self._core.set_load_stiffness(extra)
        if update_forces and F.size:
            self._core.set_p(F @ self._load_cases)
        self._amplitudes = F

    # -- stepping and statics ---------------------------------------------------

    @_one_at_a_time
    def step(self, n: int = 1) -> None:
        """n implicit steps of dt. Raises ValueError for a non-finite state, RuntimeError when a
        step fails (the state is then as before the call)."""
        if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)):
            raise TypeError(f"step count n must be an integer, got {type(n).__name__}")
        self._core.step(int(n))

    @_one_at_a_time
    def solve_static(self, load_steps: int = 1, tolerance: float = 1e-10, max_iterations: int = 50) -> int:
        """Static equilibrium f(q) + modal_forces = 0 by Newton with load stepping from the
        current q; velocities become zero. Returns the Newton iterations taken."""
        return int(self._core.solve_static(int(load_steps), float(tolerance), int(max_iterations)))

    @_one_at_a_time
    def reset(self) -> None:
        """q, velocities, modal forces and load amplitudes zero, time 0."""
        self._core.reset()
        self._set_amplitudes(np.zeros(len(self._amplitudes)), update_forces=False)

    def internal_forces(self, q: ArrayLike | None = None) -> np.ndarray:
        """(r,) internal modal forces f(q) (default: the current q)."""
        return np.asarray(self._core.evaluate(self._checked_q(q))[0])

    def tangent(self, q: ArrayLike | None = None) -> np.ndarray:
        """(r, r) tangent stiffness -df/dq at q (default: the current q)."""
        return np.asarray(self._core.evaluate(self._checked_q(q))[1])

    def energy(self, q: ArrayLike | None = None) -> float:
        """Elastic energy at q (the potential of f when A and B are fully symmetric)."""
        return float(self._core.energy(self._checked_q(q)))

    def _checked_q(self, q: ArrayLike | None) -> np.ndarray:
        if q is None:
            return np.array(self.q)
        x = np.asarray(q, dtype=np.float64)
        if x.shape != (self.n_modes,) or not np.all(np.isfinite(x)):
            raise ValueError(f"q must be a finite array of shape ({self.n_modes},)")
        return x

    # -- recovery and output -----------------------------------------------------

    @_one_at_a_time
    def displacements(self, nodes: ArrayLike | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """Nodal displacements Phi q: (n, 3) for all nodes, or (k, 3) for ``nodes`` (k,), turned
        by the partial rotation if one is set. With ``out`` (a float64 C-contiguous array of
        that shape) nothing is allocated."""
        idx = None
        if nodes is not None:
            idx = np.atleast_1d(np.asarray(nodes))
            if idx.ndim != 1 or (idx.size and not np.issubdtype(idx.dtype, np.integer)):
                raise ValueError("nodes must be a 1-D array of integer node indices")
            if idx.dtype != np.int64:
                idx = idx.astype(np.int64)
        count = self.n_nodes if idx is None else idx.size
        if out is None:
            out = np.empty((count, 3))
        rotation = None if self._partial_rotation is None else self._partial_rotation.core
        _core.recover_displacements(self._recovery_vectors, self._core.q, idx, out, rotation)
        return out

    def positions(self, out: np.ndarray | None = None) -> np.ndarray:
        """(n, 3) rest positions + displacements (into ``out`` if given)."""
        x = self.displacements(out=out)
        x += self._basis.rest_positions
        return x

    def write_frame(self, writer: TimeSeriesWriter) -> Path:
        """Write the recovered field at the current time to a TimeSeriesWriter (built on this
        body's mesh); point data "displacement" as for any simulation."""
        return writer.write(self.time, self.positions())

    # -- files --------------------------------------------------------------------

    def save(self, path: str | os.PathLike[str]) -> None:
        """Save the reduced model (basis, modal stiffness, force tensors, load cases, settings,
        the partial rotation's domains and, if present, the mesh connectivity for output) to a
        NumPy .npz file: all that
        ModalBody.load needs to run it without the full model."""
        b = self._basis
        arrays: dict[str, Any] = {
            "format_version": np.array(_FORMAT_VERSION),
            "vectors": b.vectors,
            "eigenvalues": b.eigenvalues,
            "rest_positions": b.rest_positions,
            "fixed_dofs": b.fixed_dofs,
            "interface_nodes": b.interface_nodes,
            "counts": np.array([b.n_normal_modes, b.n_extra]),
            "settings": np.array([self.dt, *self.rayleigh]),
            "recovery": np.array(self._recovery),
            "quadratic": self._quadratic,
            "cubic": self._cubic,
            "load_cases": self._load_cases,
            "load_stiffness": self._load_stiffness,
        }
        if self._partial_rotation is not None:
            arrays.update({f"partial_rotation_{k}": v for k, v in self._partial_rotation.to_arrays().items()})
        if self._mesh is not None:
            arrays["cells"] = self._mesh.cells
            arrays["cell_type"] = np.array(self._mesh.cell_type)
        np.savez(os.fspath(path), **arrays)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> ModalBody:
        """A ModalBody from a file written by save() (state at rest, t = 0).

        Raises FileNotFoundError for a missing file and ValueError naming the file and what
        is wrong with it: not a NumPy .npz archive, truncated or corrupt, not written by
        save(), or holding arrays that do not fit together."""
        if not Path(path).is_file():
            raise FileNotFoundError(f"modal body file not found: {path}")
        with Path(path).open("rb") as f:
            magic = f.read(4)
        if magic != b"PK\x03\x04":
            raise ValueError(
                f"{path} is not a corotate modal body file: save() writes a NumPy .npz (zip) archive, which starts "
                f"with the bytes PK\\x03\\x04; this file starts with {magic!r}"
            )
        try:
            return cls._load_npz(path)
        except (zipfile.BadZipFile, EOFError, zlib.error, OSError) as e:
            raise ValueError(f"{path} is truncated or corrupt: the .npz archive cannot be read ({e})") from e
        except KeyError as e:
            raise ValueError(f"{path} is not a complete corotate modal body file: it lacks the array {e}") from e
        except (ValueError, TypeError) as e:
            if str(path) in str(e):
                raise
            raise ValueError(f"{path} holds an inconsistent modal body: {e}") from e

    @classmethod
    def _load_npz(cls, path: str | os.PathLike[str]) -> ModalBody:
        with np.load(os.fspath(path), allow_pickle=False) as data:
            if "format_version" not in data or int(data["format_version"]) != _FORMAT_VERSION:
                raise ValueError(f"{path} is not a corotate modal body file (format {_FORMAT_VERSION})")
            n_normal, n_extra = (int(v) for v in data["counts"])
            basis = ModalBasis(
                vectors=np.ascontiguousarray(data["vectors"]),
                eigenvalues=data["eigenvalues"],
                rest_positions=data["rest_positions"],
                fixed_dofs=data["fixed_dofs"],
                interface_nodes=data["interface_nodes"],
                n_normal_modes=n_normal,
                n_extra=n_extra,
            )
            mesh = Mesh(basis.rest_positions, data["cells"], str(data["cell_type"])) if "cells" in data else None
            dt, alpha, beta = (float(v) for v in data["settings"])
            quadratic = data["quadratic"] if data["quadratic"].size else None
            cubic = data["cubic"] if data["cubic"].size else None
            recovery = str(data["recovery"]) if "recovery" in data else "float64"
            body = cls(
                basis, dt=dt, rayleigh=(alpha, beta), quadratic=quadratic, cubic=cubic, mesh=mesh, recovery=recovery
            )
            if data["load_cases"].size:
                body.set_load_cases(data["load_cases"], data["load_stiffness"])
            prefix = "partial_rotation_"
            if any(key.startswith(prefix) for key in data.files):
                arrays = {key[len(prefix) :]: data[key] for key in data.files if key.startswith(prefix)}
                body.partial_rotation = PartialRotation.from_arrays(basis.rest_positions, arrays)
        return body
