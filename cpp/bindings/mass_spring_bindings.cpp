// pybind11 glue for mass-spring systems (corotate._core): the MassSpring force model, the
// topology builders and the critical-step formula. Nothing but
// conversions; InvalidInput becomes ValueError and SolverFailure RuntimeError.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/integrators/critical_time_step.hpp"
#include "corotate/models/mass_spring.hpp"
#include "corotate/models/spring_builders.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

using IndexIn = py::array_t<long long, py::array::c_style | py::array::forcecast>;
using ValuesIn = py::array_t<double, py::array::c_style | py::array::forcecast>;

Vec values_from(const ValuesIn& a, py::ssize_t n, const char* what) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw InvalidInput(std::string(what) + " must have shape (" + std::to_string(n) + ",), got " +
                       std::to_string(a.ndim()) + "-d array of " + std::to_string(a.size()) + " entries");
  return Eigen::Map<const Vec>(a.data(), n);
}

// Springs from (m, 2) node pairs and per-spring k, d, l0 arrays.
std::vector<Spring> springs_from(const IndexIn& pairs, const ValuesIn& k, const ValuesIn& d, const ValuesIn& l0) {
  if (pairs.ndim() != 2 || pairs.shape(1) != 2) throw InvalidInput("springs must have shape (m, 2): node pairs");
  const py::ssize_t m = pairs.shape(0);
  const Vec K = values_from(k, m, "stiffness"), D = values_from(d, m, "damping"),
            L = values_from(l0, m, "rest_lengths");
  std::vector<Spring> springs(m);
  for (py::ssize_t s = 0; s < m; ++s) {
    for (int e = 0; e < 2; ++e) {
      const long long v = pairs.data()[2 * s + e];
      if (v < 0 || v > std::numeric_limits<int>::max())
        throw InvalidInput("spring " + std::to_string(s) + " refers to node " + std::to_string(v) + ", out of range");
    }
    springs[s] =
        Spring{static_cast<int>(pairs.data()[2 * s]), static_cast<int>(pairs.data()[2 * s + 1]), K[s], D[s], L[s]};
  }
  return springs;
}

std::unique_ptr<MassSpring> make_mass_spring(const PointsIn& points, const IndexIn& pairs, const ValuesIn& k,
                                             const ValuesIn& d, const ValuesIn& l0, const ValuesIn& masses) {
  const Nodes X = nodes_from(points, "nodes");
  return std::make_unique<MassSpring>(X, springs_from(pairs, k, d, l0), values_from(masses, X.cols(), "masses"));
}

py::dict system_dict(const SpringSystem& s) {
  const Index m = static_cast<Index>(s.springs.size());
  Eigen::Matrix<long long, Eigen::Dynamic, 2, Eigen::RowMajor> pairs(m, 2);
  Vec k(m), d(m), l0(m);
  Eigen::VectorXi kinds(m);
  for (Index i = 0; i < m; ++i) {
    pairs(i, 0) = s.springs[i].i;
    pairs(i, 1) = s.springs[i].j;
    k[i] = s.springs[i].stiffness;
    d[i] = s.springs[i].damping;
    l0[i] = s.springs[i].rest_length;
    kinds[i] = s.kinds[i];
  }
  py::dict out;
  out["nodes"] = Eigen::MatrixXd(s.nodes.transpose());
  out["springs"] = pairs;
  out["stiffness"] = k;
  out["damping"] = d;
  out["rest_lengths"] = l0;
  out["kinds"] = kinds;
  out["masses"] = s.masses;
  out["cells"] = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>(s.cells);
  out["cell_type"] = s.cell_type;
  return out;
}

}  // namespace

void bind_mass_spring(py::module_& m) {
  py::class_<MassSpring, ForceModel>(m, "MassSpring")
      .def(py::init(&make_mass_spring), py::arg("nodes"), py::arg("springs"), py::arg("stiffness"), py::arg("damping"),
           py::arg("rest_lengths"), py::arg("masses"),
           "Mass-spring force model: nodes (n, 3), springs (m, 2) node pairs, stiffness, damping, rest_lengths (m,), "
           "masses (n,).")
      .def_property_readonly("num_springs", &MassSpring::num_springs)
      .def(
          "damping_forces",
          [](MassSpring& self, const PointsIn& x, const PointsIn& v) {
            const Nodes X = checked_positions(self, x, "positions"),
                        V = checked_positions(self, v, "velocities", "velocity");
            Nodes f = Nodes::Zero(3, X.cols());
            self.add_damping_forces(X, V, f);
            return Eigen::MatrixXd(f.transpose());
          },
          py::arg("positions"), py::arg("velocities"), "Damping forces of eq. (2), (n, 3).")
      .def(
          "damping_csr",
          [](MassSpring& self, const PointsIn& x) {
            BlockSparseMatrix C = self.pattern();
            C.set_zero();
            self.add_damping_matrix(checked_positions(self, x, "positions"), 1.0, C);
            return to_csr(C);
          },
          py::arg("positions"))
      .def("stiffness_bound_csr", [](MassSpring& self) {
        BlockSparseMatrix B = self.pattern();
        B.set_zero();
        self.add_stiffness_bound(1.0, B);
        return to_csr(B);
      });

  m.def(
      "cloth_grid",
      [](int nx, int ny, double width, double height, double E, double thickness, double density, double bending,
         double beta) {
        return system_dict(cloth_grid({nx, ny, width, height, E, thickness, density, bending, beta}));
      },
      py::arg("nx"), py::arg("ny"), py::arg("width"), py::arg("height"), py::arg("youngs_modulus"),
      py::arg("thickness"), py::arg("density"), py::arg("bending"), py::arg("beta"));
  m.def(
      "cube_lattice",
      [](int nx, int ny, int nz, const Vec3& size, double E, double density, double beta) {
        return system_dict(cube_lattice({nx, ny, nz, size.x(), size.y(), size.z(), E, density, beta}));
      },
      py::arg("nx"), py::arg("ny"), py::arg("nz"), py::arg("size"), py::arg("youngs_modulus"), py::arg("density"),
      py::arg("beta"));
  m.def(
      "springs_from_mesh",
      [](const PointsIn& points, const CellsIn& cells, const std::string& cell_type, double E, double density,
         double beta, bool diagonals) {
        return system_dict(
            springs_from_mesh(nodes_from(points, "points"), cells_from(cells), cell_type, E, density, beta, diagonals));
      },
      py::arg("points"), py::arg("cells"), py::arg("cell_type"), py::arg("youngs_modulus"), py::arg("density"),
      py::arg("beta"), py::arg("diagonals"));

  m.def("critical_time_step", &critical_time_step, py::arg("omega_sq"), py::arg("damping_rate"),
        "(sqrt(c^2 + 4 w^2) - c) / w^2: stability limit of leapfrog on x'' = -w^2 x - c x'.");
}
