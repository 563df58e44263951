// pybind11 glue for corotate._core: nothing but conversions. C++ InvalidInput becomes
// ValueError and SolverFailure becomes RuntimeError (pybind11 maps std::invalid_argument
// and std::runtime_error that way).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/elements/element_matrices.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/models/rotation_extraction.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

void bind_mass_spring(py::module_& m);  // mass_spring_bindings.cpp
void bind_hyperelastic(py::module_& m);  // hyperelastic_bindings.cpp

namespace {


// Block matrix from a symmetric COO description of a 3n x 3n matrix.
BlockSparseMatrix from_coo(Index size, const Eigen::VectorXi& rows, const Eigen::VectorXi& cols, const Eigen::VectorXd& values) {
  if (size % 3 != 0) throw InvalidInput("matrix size must be a multiple of 3");
  if (rows.size() != cols.size() || rows.size() != values.size()) throw InvalidInput("rows, cols and values differ in length");
  std::vector<std::pair<int, int>> pairs;
  for (Index k = 0; k < rows.size(); ++k) {
    if (rows[k] < 0 || rows[k] >= size || cols[k] < 0 || cols[k] >= size) throw InvalidInput("matrix index out of range");
    pairs.emplace_back(rows[k] / 3, cols[k] / 3);
  }
  BlockSparseMatrix A = BlockSparseMatrix::from_pairs(size / 3, pairs);
  for (Index k = 0; k < rows.size(); ++k)
    A.block(A.block_index(rows[k] / 3, cols[k] / 3))(rows[k] % 3, cols[k] % 3) += values[k];
  return A;
}

py::dict solve_stats_dict(const SolveStats& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["residual"] = s.relative_residual;
  d["converged"] = s.converged;
  return d;
}

template <class E>
py::dict element_matrices_dict(const PointsIn& points, const Material& material) {
  const Nodes X = nodes_from(points, "element nodes");
  if (X.cols() != E::num_nodes) throw InvalidInput(std::string(E::name) + " needs " + std::to_string(E::num_nodes) + " nodes");
  material.validate();
  const auto m = compute_element_matrices<E>(X, material, 0);
  py::dict d;
  d["stiffness"] = Eigen::MatrixXd(m.stiffness);
  d["mass"] = Eigen::MatrixXd(m.mass);
  d["lumped_mass"] = Eigen::VectorXd(m.lumped_mass);
  d["volume"] = m.volume;
  d["centre_gradient"] = Eigen::MatrixXd(m.centre_gradient);
  return d;
}

std::unique_ptr<LinearSolver> make_solver(const std::string& kind, const PCGSettings& pcg) {
  if (kind == "pcg") return std::make_unique<PCG>(pcg);
  if (kind == "direct") return std::make_unique<DirectSolver>();
  throw InvalidInput("unknown solver '" + kind + "' (choose 'pcg' or 'direct')");
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "corotate C++ core: element matrices, force models, solvers, implicit stepping.";

  py::class_<Material>(m, "Material")
      .def(py::init([](double E, double nu, double density) {
             Material mat{E, nu, density};
             mat.validate();
             return mat;
           }),
           py::arg("youngs_modulus"), py::arg("poisson_ratio"), py::arg("density"))
      .def_readonly("youngs_modulus", &Material::youngs_modulus)
      .def_readonly("poisson_ratio", &Material::poisson_ratio)
      .def_readonly("density", &Material::density)
      .def_property_readonly("lame_lambda", &Material::lame_lambda)
      .def_property_readonly("lame_mu", &Material::lame_mu)
      .def("elasticity_matrix", &Material::elasticity_matrix);

  m.def("element_matrices", [](const std::string& cell_type, const PointsIn& points, const Material& material) {
    if (cell_type == Tet4::name) return element_matrices_dict<Tet4>(points, material);
    if (cell_type == Hex8::name) return element_matrices_dict<Hex8>(points, material);
    if (cell_type == Hex20::name) return element_matrices_dict<Hex20>(points, material);
    throw InvalidInput("unsupported cell type '" + cell_type + "'");
  }, py::arg("cell_type"), py::arg("points"), py::arg("material"),
        "Precomputed matrices of one element: stiffness (3k x 3k), consistent mass (k x k scalar), lumped_mass (k), volume.");

  m.def("polar_rotation", [](const Mat3& F) { return polar_rotation_svd(F); }, py::arg("F"));
  m.def("extract_rotation", [](const Mat3& F) {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    return extract_rotation(F, q);
  }, py::arg("F"), "Rotation of F by the warm-startable iteration, started from the identity.");

  py::class_<ForceModel>(m, "ForceModel")
      .def(py::init([](const std::string& model, const std::string& cell_type, const PointsIn& points, const CellsIn& cells,
                       const Material& material) {
             return make_model(model, cell_type, nodes_from(points, "points"), cells_from(cells), material);
           }),
           py::arg("model"), py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"))
      .def_property_readonly("name", &ForceModel::name)
      .def_property_readonly("num_nodes", &ForceModel::num_nodes)
      .def("internal_forces", [](ForceModel& self, const PointsIn& x) {
        const Nodes X = checked_positions(self, x);
        self.update(X);
        Nodes f = Nodes::Zero(3, X.cols());
        self.add_forces(X, f);
        return Eigen::MatrixXd(f.transpose());
      }, py::arg("positions"), "Internal elastic forces (n, 3) at positions (n, 3).")
      .def("energy", [](ForceModel& self, const PointsIn& x) {
        const Nodes X = checked_positions(self, x);
        self.update(X);
        return self.energy(X);
      }, py::arg("positions"))
      .def("stiffness_csr", [](ForceModel& self, const PointsIn& x) {
        const Nodes X = checked_positions(self, x);
        self.update(X);
        BlockSparseMatrix K = self.pattern();
        K.set_zero();
        self.add_stiffness(1.0, K);
        return to_csr(K);
      }, py::arg("positions"), "Stiffness at positions as a CSR triple (data, indices, indptr).")
      .def("tangent_csr", [](ForceModel& self, const PointsIn& x) {
        const Nodes X = checked_positions(self, x);
        self.update(X);
        BlockSparseMatrix K = self.pattern();
        K.set_zero();
        self.add_tangent_stiffness(X, 1.0, K);
        return to_csr(K);
      }, py::arg("positions"), "Exact tangent -df/dx at positions as a CSR triple (see add_tangent_stiffness).")
      .def("mass_csr", [](ForceModel& self, bool lumped) { return to_csr(self.mass_matrix(lumped)); }, py::arg("lumped"));

  py::class_<BlockSparseMatrix>(m, "BlockSparseMatrix")
      .def(py::init(&from_coo), py::arg("size"), py::arg("rows"), py::arg("cols"), py::arg("values"),
           "Symmetric 3x3-block matrix from COO entries of a size x size matrix (size a multiple of 3).")
      .def("to_csr", &to_csr)
      .def("multiply", [](const BlockSparseMatrix& A, const Vec& x) {
        if (x.size() != A.num_dofs()) throw InvalidInput("vector length does not match the matrix");
        Vec y(x.size());
        A.multiply(x, y);
        return y;
      });

  py::class_<PCGSettings>(m, "PCGSettings")
      .def(py::init([](int max_iterations, double tolerance, bool warm_start, const std::string& preconditioner) {
             PCGSettings s{max_iterations, tolerance, warm_start, preconditioner_kind_from_name(preconditioner)};
             PCG check(s);  // validates
             return s;
           }),
           py::arg("max_iterations") = 20, py::arg("tolerance") = 1e-6, py::arg("warm_start") = true,
           py::arg("preconditioner") = "block_jacobi")
      .def_readonly("max_iterations", &PCGSettings::max_iterations)
      .def_readonly("tolerance", &PCGSettings::tolerance)
      .def_readonly("warm_start", &PCGSettings::warm_start)
      .def_property_readonly("preconditioner", [](const PCGSettings& s) { return preconditioner_name(s.preconditioner); });

  m.def("solve_linear", [](const BlockSparseMatrix& A, const Vec& b, const std::optional<Vec>& x0, const std::string& solver,
                           const PCGSettings& pcg, const std::optional<PointsIn>& geometry) {
    if (b.size() != A.num_dofs()) throw InvalidInput("right-hand side length does not match the matrix");
    Vec x = x0 ? *x0 : Vec::Zero(b.size());
    if (x.size() != b.size()) throw InvalidInput("initial guess length does not match the matrix");
    auto s = make_solver(solver, pcg);
    if (geometry) s->set_geometry(nodes_from(*geometry, "geometry"));
    const SolveStats stats = s->solve(A, b, x);
    return py::make_tuple(x, solve_stats_dict(stats));
  }, py::arg("A"), py::arg("b"), py::arg("x0") = py::none(), py::arg("solver") = "pcg", py::arg("pcg") = PCGSettings{},
        py::arg("geometry") = py::none(),
        "Solve A x = b with 'pcg' (settings pcg, initial guess x0) or 'direct'. geometry: (n, 3) node\n"
        "positions, needed by the two_level preconditioner. Returns (x, stats).");

  py::class_<ImplicitEulerSettings>(m, "ImplicitEulerSettings")
      .def(py::init([](double dt, double alpha, double beta, bool lumped, int newton_iterations, double newton_tolerance) {
             ImplicitEulerSettings s{dt, alpha, beta, lumped, newton_iterations, newton_tolerance};
             s.validate();
             return s;
           }),
           py::arg("time_step"), py::arg("rayleigh_alpha") = 0.0, py::arg("rayleigh_beta") = 0.0, py::arg("lumped_mass") = false,
           py::arg("newton_iterations") = 0, py::arg("newton_tolerance") = 1e-6)
      .def_readonly("newton_iterations", &ImplicitEulerSettings::newton_iterations)
      .def_readonly("newton_tolerance", &ImplicitEulerSettings::newton_tolerance)
      .def_readonly("time_step", &ImplicitEulerSettings::time_step)
      .def_readonly("rayleigh_alpha", &ImplicitEulerSettings::rayleigh_alpha)
      .def_readonly("rayleigh_beta", &ImplicitEulerSettings::rayleigh_beta)
      .def_readonly("lumped_mass", &ImplicitEulerSettings::lumped_mass);

  py::class_<Simulation>(m, "Simulation")
      .def(py::init([](const std::string& model, const std::string& cell_type, const PointsIn& points, const CellsIn& cells,
                       const Material& material, const ImplicitEulerSettings& settings, const std::string& solver,
                       const PCGSettings& pcg, double thickness, bool project_psd) {
             return std::make_unique<Simulation>(make_model(model, cell_type, nodes_from(points, "points"), cells_from(cells),
                                                            material, ModelOptions{thickness, project_psd}),
                                                 settings, make_solver(solver, pcg));
           }),
           py::arg("model"), py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"),
           py::arg("settings"), py::arg("solver") = "pcg", py::arg("pcg") = PCGSettings{}, py::arg("thickness") = 1.0,
           py::arg("project_psd") = false)
      .def_property_readonly("positions", [](py::object self) { return node_view(self.cast<Simulation&>().positions(), self); })
      .def_property_readonly("velocities", [](py::object self) { return node_view(self.cast<Simulation&>().velocities(), self); })
      .def_property_readonly("external_forces", [](py::object self) { return node_view(self.cast<Simulation&>().external_forces(), self); })
      .def_property_readonly("gravity_forces", [](const Simulation& s) { return Eigen::MatrixXd(s.gravity_forces().transpose()); })
      .def_property_readonly("time", &Simulation::time)
      .def_property_readonly("num_nodes", &Simulation::num_nodes)
      .def_property("gravity", &Simulation::gravity, &Simulation::set_gravity)
      .def_property("fixed_nodes", &Simulation::fixed_nodes, &Simulation::set_fixed_nodes)
      .def_property("settings", &Simulation::settings, &Simulation::set_settings)
      .def("set_solver", [](Simulation& s, const std::string& solver, const PCGSettings& pcg) { s.set_solver(make_solver(solver, pcg)); },
           py::arg("solver"), py::arg("pcg") = PCGSettings{})
      .def("step", &Simulation::step, py::arg("n") = 1, py::call_guard<py::gil_scoped_release>())
      .def("solve_static", [](Simulation& s, int load_steps, double tolerance, int max_iterations,
                              const std::optional<PointsIn>& prescribed) {
        std::optional<Nodes> target;
        if (prescribed) {
          target = nodes_from(*prescribed, "prescribed positions");
          if (target->cols() != s.num_nodes()) throw InvalidInput("prescribed positions must have one row per node");
        }
        const StaticResult r = s.solve_static({load_steps, tolerance, max_iterations}, target ? &*target : nullptr);
        py::dict d;
        d["residual_history"] = r.residual_history;
        d["iterations"] = r.total_iterations;
        return d;
      }, py::arg("load_steps") = 1, py::arg("tolerance") = 1e-8, py::arg("max_iterations") = 100,
         py::arg("prescribed") = py::none())
      .def("internal_forces", [](Simulation& s) {
        s.model().update(s.positions());
        Nodes f = Nodes::Zero(3, s.num_nodes());
        s.model().add_forces(s.positions(), f);
        return Eigen::MatrixXd(f.transpose());
      })
      .def("energy", [](Simulation& s) { s.model().update(s.positions()); return s.model().energy(s.positions()); })
      .def_property_readonly("stats", [](const Simulation& s) {
        const auto& st = s.stats();
        py::dict d;
        d["steps"] = st.steps;
        d["iterations"] = st.last.solve.iterations;
        d["newton_iterations"] = st.last.newton_iterations;
        d["newton_residuals"] = st.last.newton_residuals;
        d["residual"] = st.last.solve.relative_residual;
        d["converged"] = st.last.solve.converged;
        d["iterations_per_step"] = st.iterations_per_step();
        d["ms_per_step"] = st.ms_per_step();
        d["rotation_ms"] = st.last.rotation_ms;
        d["assembly_ms"] = st.last.assembly_ms;
        d["solve_ms"] = st.last.solve_ms;
        d["simulated_time"] = st.simulated_time;
        d["wall_time"] = st.wall_ms * 1e-3;
        d["real_time_ratio"] = st.real_time_ratio();
        return d;
      })
      .def("reset_stats", &Simulation::reset_stats);

  bind_mass_spring(m);  // after ForceModel, which MassSpring derives from
  bind_hyperelastic(m);  // after ForceModel, which it returns
}
