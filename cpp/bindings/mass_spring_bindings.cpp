// pybind11 glue for mass-spring systems and explicit stepping (corotate._core): the
// MassSpring force model, the topology builders and ExplicitSimulation. Nothing but
// conversions; InvalidInput becomes ValueError and SolverFailure RuntimeError.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/explicit_simulation.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/models/spring_builders.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

using IndexIn = py::array_t<long long, py::array::c_style | py::array::forcecast>;
using ValuesIn = py::array_t<double, py::array::c_style | py::array::forcecast>;

Vec values_from(const ValuesIn& a, py::ssize_t n, const char* what) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw InvalidInput(std::string(what) + " must have shape (" + std::to_string(n) + ",), got " + std::to_string(a.ndim()) +
                       "-d array of " + std::to_string(a.size()) + " entries");
  return Eigen::Map<const Vec>(a.data(), n);
}

// Springs from (m, 2) node pairs and per-spring k, d, l0 arrays.
std::vector<Spring> springs_from(const IndexIn& pairs, const ValuesIn& k, const ValuesIn& d, const ValuesIn& l0) {
  if (pairs.ndim() != 2 || pairs.shape(1) != 2) throw InvalidInput("springs must have shape (m, 2): node pairs");
  const py::ssize_t m = pairs.shape(0);
  const Vec K = values_from(k, m, "stiffness"), D = values_from(d, m, "damping"), L = values_from(l0, m, "rest_lengths");
  std::vector<Spring> springs(m);
  for (py::ssize_t s = 0; s < m; ++s) {
    for (int e = 0; e < 2; ++e) {
      const long long v = pairs.data()[2 * s + e];
      if (v < 0 || v > std::numeric_limits<int>::max())
        throw InvalidInput("spring " + std::to_string(s) + " refers to node " + std::to_string(v) + ", out of range");
    }
    springs[s] = Spring{static_cast<int>(pairs.data()[2 * s]), static_cast<int>(pairs.data()[2 * s + 1]), K[s], D[s], L[s]};
  }
  return springs;
}

std::unique_ptr<MassSpring> make_mass_spring(const PointsIn& points, const IndexIn& pairs, const ValuesIn& k, const ValuesIn& d,
                                             const ValuesIn& l0, const ValuesIn& masses) {
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

py::dict eigen_dict(const EigenEstimate& e) {
  py::dict d;
  d["value"] = e.value;
  d["ritz"] = e.ritz;
  d["residual"] = e.residual;
  d["iterations"] = e.iterations;
  return d;
}

py::dict stability_dict(const StabilityEstimate& s) {
  py::dict d;
  d["critical_step"] = s.critical_step;
  d["omega_max"] = s.omega_max;
  d["lambda_max"] = s.stiffness.value;
  d["damping_rate"] = s.damping_rate;
  d["bound"] = s.bound;
  d["stiffness"] = eigen_dict(s.stiffness);
  d["damping"] = eigen_dict(s.damping);
  return d;
}

ExplicitSettings make_settings(double dt, const std::string& integrator, const std::string& policy,
                               const std::string& on_unstable, double safety, double mass_damping) {
  ExplicitSettings s;
  s.time_step = dt;
  s.scheme = explicit_scheme_from_name(integrator);
  s.policy = time_step_policy_from_name(policy);
  s.on_unstable = on_unstable_from_name(on_unstable);
  s.safety = safety;
  s.mass_damping = mass_damping;
  s.validate();
  return s;
}

const char* policy_name(TimeStepPolicy p) { return p == TimeStepPolicy::Fixed ? "fixed" : "online"; }
const char* on_unstable_name(OnUnstable o) {
  return o == OnUnstable::Substep ? "substep" : o == OnUnstable::Raise ? "raise" : "allow";
}

}  // namespace

void bind_mass_spring(py::module_& m) {
  py::class_<MassSpring, ForceModel>(m, "MassSpring")
      .def(py::init(&make_mass_spring), py::arg("nodes"), py::arg("springs"), py::arg("stiffness"), py::arg("damping"),
           py::arg("rest_lengths"), py::arg("masses"),
           "Mass-spring force model: nodes (n, 3), springs (m, 2) node pairs, stiffness, damping, rest_lengths (m,), masses (n,).")
      .def_property_readonly("num_springs", &MassSpring::num_springs)
      .def("damping_forces", [](MassSpring& self, const PointsIn& x, const PointsIn& v) {
        const Nodes X = checked_positions(self, x, "positions"), V = checked_positions(self, v, "velocities", "velocity");
        Nodes f = Nodes::Zero(3, X.cols());
        self.add_damping_forces(X, V, f);
        return Eigen::MatrixXd(f.transpose());
      }, py::arg("positions"), py::arg("velocities"), "Damping forces of eq. (2), (n, 3).")
      .def("damping_csr", [](MassSpring& self, const PointsIn& x) {
        self.update(checked_positions(self, x, "positions"));
        BlockSparseMatrix C = self.pattern();
        C.set_zero();
        self.add_damping_matrix(1.0, C);
        return to_csr(C);
      }, py::arg("positions"))
      .def("stiffness_bound_csr", [](MassSpring& self) {
        BlockSparseMatrix B = self.pattern();
        B.set_zero();
        self.add_stiffness_bound(1.0, B);
        return to_csr(B);
      });

  m.def("cloth_grid", [](int nx, int ny, double width, double height, double E, double thickness, double density,
                         double bending, double beta) {
    return system_dict(cloth_grid({nx, ny, width, height, E, thickness, density, bending, beta}));
  }, py::arg("nx"), py::arg("ny"), py::arg("width"), py::arg("height"), py::arg("youngs_modulus"), py::arg("thickness"),
        py::arg("density"), py::arg("bending"), py::arg("beta"));
  m.def("cube_lattice", [](int nx, int ny, int nz, const Vec3& size, double E, double density, double beta) {
    return system_dict(cube_lattice({nx, ny, nz, size.x(), size.y(), size.z(), E, density, beta}));
  }, py::arg("nx"), py::arg("ny"), py::arg("nz"), py::arg("size"), py::arg("youngs_modulus"), py::arg("density"), py::arg("beta"));
  m.def("springs_from_mesh", [](const PointsIn& points, const CellsIn& cells, const std::string& cell_type, double E,
                                double density, double beta, bool diagonals) {
    return system_dict(springs_from_mesh(nodes_from(points, "points"), cells_from(cells), cell_type, E, density, beta,
                                         diagonals));
  }, py::arg("points"), py::arg("cells"), py::arg("cell_type"), py::arg("youngs_modulus"), py::arg("density"), py::arg("beta"),
        py::arg("diagonals"));

  m.def("critical_time_step", &critical_time_step, py::arg("omega_sq"), py::arg("damping_rate"),
        "(sqrt(c^2 + 4 w^2) - c) / w^2: stability limit of leapfrog on x'' = -w^2 x - c x'.");

  py::class_<ExplicitSimulation>(m, "ExplicitSimulation")
      .def(py::init([](const PointsIn& points, const IndexIn& pairs, const ValuesIn& k, const ValuesIn& d, const ValuesIn& l0,
                       const ValuesIn& masses, double dt, const std::string& integrator, const std::string& policy,
                       const std::string& on_unstable, double safety, double mass_damping) {
             return std::make_unique<ExplicitSimulation>(make_mass_spring(points, pairs, k, d, l0, masses),
                                                         make_settings(dt, integrator, policy, on_unstable, safety, mass_damping));
           }),
           py::arg("nodes"), py::arg("springs"), py::arg("stiffness"), py::arg("damping"), py::arg("rest_lengths"),
           py::arg("masses"), py::arg("time_step"), py::arg("integrator"), py::arg("policy"), py::arg("on_unstable"),
           py::arg("safety"), py::arg("mass_damping"))
      // A finite-element body (any model of make_model) stepped explicitly with its lumped mass.
      .def(py::init([](const std::string& model, const std::string& cell_type, const PointsIn& points,
                       const CellsIn& cells, const Material& material, double thickness, double dt,
                       const std::string& integrator, const std::string& policy, const std::string& on_unstable,
                       double safety, double mass_damping) {
             return std::make_unique<ExplicitSimulation>(
                 make_model(model, cell_type, nodes_from(points, "points"), cells_from(cells), material,
                            ModelOptions{thickness, false}),
                 make_settings(dt, integrator, policy, on_unstable, safety, mass_damping));
           }),
           py::arg("model"), py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"),
           py::arg("thickness"), py::arg("time_step"), py::arg("integrator"), py::arg("policy"), py::arg("on_unstable"),
           py::arg("safety"), py::arg("mass_damping"))
      .def_property_readonly("positions", [](py::object self) { return node_view(self.cast<ExplicitSimulation&>().positions(), self); })
      .def_property_readonly("velocities", [](py::object self) { return node_view(self.cast<ExplicitSimulation&>().velocities(), self); })
      .def_property_readonly("external_forces",
                             [](py::object self) { return node_view(self.cast<ExplicitSimulation&>().external_forces(), self); })
      .def_property_readonly("time", &ExplicitSimulation::time)
      .def_property("gravity", &ExplicitSimulation::gravity, &ExplicitSimulation::set_gravity)
      .def_property("fixed_nodes", &ExplicitSimulation::fixed_nodes, &ExplicitSimulation::set_fixed_nodes)
      .def("configure", [](ExplicitSimulation& s, double dt, const std::string& integrator, const std::string& policy,
                           const std::string& on_unstable, double safety, double mass_damping) {
        s.set_settings(make_settings(dt, integrator, policy, on_unstable, safety, mass_damping));
      }, py::arg("time_step"), py::arg("integrator"), py::arg("policy"), py::arg("on_unstable"), py::arg("safety"),
           py::arg("mass_damping"))
      .def_property_readonly("settings", [](const ExplicitSimulation& s) {
        const auto& st = s.settings();
        py::dict d;
        d["time_step"] = st.time_step;
        d["integrator"] = explicit_scheme_name(st.scheme);
        d["policy"] = policy_name(st.policy);
        d["on_unstable"] = on_unstable_name(st.on_unstable);
        d["safety"] = st.safety;
        d["mass_damping"] = st.mass_damping;
        return d;
      })
      .def("stability", [](ExplicitSimulation& s) { return stability_dict(s.stability()); })
      .def("estimate_stability", [](ExplicitSimulation& s, bool bound) { return stability_dict(s.estimate_stability(bound)); },
           py::arg("bound"))
      .def("step", &ExplicitSimulation::step, py::arg("n") = 1, py::call_guard<py::gil_scoped_release>())
      .def("kinetic_energy", &ExplicitSimulation::kinetic_energy)
      .def("energy", [](ExplicitSimulation& s) {
        s.model().update(s.positions());
        return s.model().energy(s.positions());
      })
      .def("internal_forces", [](ExplicitSimulation& s) {
        Nodes f = Nodes::Zero(3, s.num_nodes());
        s.model().update(s.positions());
        s.model().add_forces(s.positions(), f);
        return Eigen::MatrixXd(f.transpose());
      })
      .def("damping_forces", [](ExplicitSimulation& s) {
        // The model's own damping forces: all forces at (x, v) minus the elastic ones.
        Nodes f = Nodes::Zero(3, s.num_nodes());
        s.model().add_explicit_forces(s.positions(), s.velocities(), f);
        s.model().update(s.positions());
        Nodes elastic = Nodes::Zero(3, s.num_nodes());
        s.model().add_forces(s.positions(), elastic);
        return Eigen::MatrixXd((f - elastic).transpose());
      })
      .def_property_readonly("stats", [](const ExplicitSimulation& s) {
        const auto& st = s.stats();
        py::dict d;
        d["steps"] = st.steps;
        d["substeps"] = st.substeps;
        d["last_substeps"] = st.last_substeps;
        d["last_substep"] = st.last_substep;
        d["ms_per_step"] = st.ms_per_step();
        d["simulated_time"] = st.simulated_time;
        d["wall_time"] = st.wall_ms * 1e-3;
        d["estimate_time"] = st.estimate_ms * 1e-3;
        d["estimates"] = st.estimates;
        d["real_time_ratio"] = st.real_time_ratio();
        return d;
      })
      .def("reset_stats", &ExplicitSimulation::reset_stats);
}
