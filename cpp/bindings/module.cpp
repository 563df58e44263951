// pybind11 glue for corotate._core: nothing but conversions. C++ InvalidInput becomes
// ValueError and SolverFailure becomes RuntimeError (pybind11 maps std::invalid_argument
// and std::runtime_error that way).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/build_info.hpp"
#include "corotate/elements/element_matrices.hpp"
#include "corotate/integrators/integrator.hpp"
#include "corotate/models/joined_model.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/models/rotation_extraction.hpp"
#include "corotate/parallel.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

void bind_mass_spring(py::module_& m);  // mass_spring_bindings.cpp
void bind_hyperelastic(py::module_& m);  // hyperelastic_bindings.cpp
void bind_simulation(py::module_& m);  // simulation_bindings.cpp
void bind_contact(py::module_& m);     // contact_bindings.cpp
void bind_feedback(py::module_& m);    // feedback_bindings.cpp
void bind_modal(py::module_& m);       // modal_bindings.cpp
void bind_floating_frame(py::module_& m);  // floating_frame_bindings.cpp
void bind_embedding(py::module_& m);  // embedding_bindings.cpp
void bind_cell_types(py::module_& m);  // cell_type_bindings.cpp
void bind_meshes(py::module_& m);  // meshes_bindings.cpp
void bind_materials(py::module_& m);  // material_bindings.cpp
std::unique_ptr<LinearSolver> make_solver(const std::string& kind, const PCGSettings& pcg);  // simulation_bindings.cpp

namespace {

const PCGSettings kPCG{};  // defaults

// Block matrix from a symmetric COO description of a 3n x 3n matrix.
BlockSparseMatrix from_coo(Index size, const Eigen::VectorXi& rows, const Eigen::VectorXi& cols,
                           const Eigen::VectorXd& values) {
  if (size % 3 != 0) throw InvalidInput("matrix size must be a multiple of 3");
  if (rows.size() != cols.size() || rows.size() != values.size())
    throw InvalidInput("rows, cols and values differ in length");
  std::vector<std::pair<int, int>> pairs;
  for (Index k = 0; k < rows.size(); ++k) {
    if (rows[k] < 0 || rows[k] >= size || cols[k] < 0 || cols[k] >= size)
      throw InvalidInput("matrix index out of range");
    pairs.emplace_back(rows[k] / 3, cols[k] / 3);
  }
  BlockSparseMatrix A = BlockSparseMatrix::from_pairs(size / 3, pairs);
  for (Index k = 0; k < rows.size(); ++k)
    A.block(A.block_index(rows[k] / 3, cols[k] / 3))(rows[k] % 3, cols[k] % 3) += values[k];
  return A;
}

py::tuple stiffness_csr(ForceModel& model, const Nodes& x, StiffnessKind kind) {
  BlockSparseMatrix K = model.pattern();
  K.set_zero();
  model.add_stiffness(x, kind, 1.0, K);
  return to_csr(K);
}

py::dict solve_stats_dict(const SolveStats& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["residual"] = s.relative_residual;
  d["converged"] = s.converged;
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "corotate C++ core: element matrices, force models, solvers, implicit and explicit stepping.";
#ifdef COROTATE_VERSION
  m.attr("__version__") = COROTATE_VERSION;
#endif
  // The name lists Python offers as choices: defined once, here in C++.
  py::enum_<PreconditionerKind>(m, "PreconditionerKind")
      .value("NONE", PreconditionerKind::None)
      .value("JACOBI", PreconditionerKind::Jacobi)
      .value("BLOCK_JACOBI", PreconditionerKind::BlockJacobi)
      .value("REFERENCE_FACTOR", PreconditionerKind::ReferenceFactor)
      .value("TWO_LEVEL", PreconditionerKind::TwoLevel)
      .value("AUTO", PreconditionerKind::Auto);
  m.def("model_names", &model_names, "Every force model name.");
  m.def("models_for_cell_type", &models_for_cell_type, py::arg("cell_type"), "The models available for a cell type.");
  m.def("preconditioner_names", &preconditioner_names, "Every PCG preconditioner name.");
  m.def("integrator_names", &integrator_names, "Every integrator name.");
  m.def(
      "explicit_integrator_names",
      [] {
        std::vector<std::string> out;
        for (const auto& name : integrator_names())
          if (is_explicit(integrator_from_name(name))) out.push_back(name);
        return out;
      },
      "The explicit integrators.");
  m.def("time_step_policy_names", &time_step_policy_names);
  m.def("failure_policy_names", &failure_policy_names);
  m.def("set_threads", &set_num_threads, py::arg("n"),
        "Threads of the element sweeps, matrix-vector products and smoother (process-wide; 1 by default).");
  m.def("threads", &num_threads, "The thread count set by set_threads.");
  m.def("available_threads", &available_threads, "Threads the hardware offers (1 without OpenMP).");
  m.def("have_openmp", &have_openmp, "Whether the core was built with OpenMP (else it runs on one thread).");
  m.def(
      "build_info",
      [] {
        const BuildInfo info = build_info();
        py::dict d;
        d["cholmod"] = info.cholmod;
        d["openmp"] = info.openmp;
        d["cpu_clones"] = info.cpu_clones;
        d["instruction_set"] = info.instruction_set;
        return d;
      },
      "What this build has: cholmod (SuiteSparse direct solves, else the library's own supernodal Cholesky), "
      "openmp (threads), cpu_clones (hot loops compiled for several instruction sets) and instruction_set (the "
      "one they run at on this CPU).");
  m.def("on_unstable_names", &on_unstable_names);

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
      .def_readonly("law", &Material::law)
      .def_readonly("parameters", &Material::parameters)
      .def_property_readonly("lame_lambda", &Material::lame_lambda)
      .def_property_readonly("lame_mu", &Material::lame_mu)
      .def("elasticity_matrix", &Material::elasticity_matrix);
  bind_materials(m);  // after Material, which it takes

  m.def("polar_rotation", [](const Mat3& F) { return polar_rotation_svd(F); }, py::arg("F"));
  m.def(
      "extract_rotation",
      [](const Mat3& F) {
        Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
        return extract_rotation(F, q);
      },
      py::arg("F"), "Rotation of F by the warm-startable iteration, started from the identity.");

  py::class_<ForceModel>(m, "ForceModel")
      .def(py::init([](const std::string& model, const std::string& cell_type, const PointsIn& points,
                       const CellsIn& cells, const RegionMaterials& material, double thickness, bool project_psd) {
             return make_model(model, cell_type, nodes_from(points, "points"), cells_from(cells), material,
                               ModelOptions{thickness, project_psd});
           }),
           py::arg("model"), py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"),
           py::arg("thickness") = ModelOptions{}.thickness, py::arg("project_psd") = ModelOptions{}.project_psd,
           "Force model by name (see model_names) on one cell type: thickness of triangle sheets [m], project_psd\n"
           "(clamp each element stiffness to positive semi-definite).")
      .def_static(
          "joined",
          [](const std::vector<const ForceModel*>& parts) -> std::unique_ptr<ForceModel> {
            return std::make_unique<JoinedModel>(parts);
          },
          py::arg("parts"),
          "One model of several bodies' models side by side (copies of them), their nodes one body after the\n"
          "other: a scene of bodies of different cell types or force models.")
      .def_property_readonly("name", &ForceModel::name)
      .def_property_readonly("num_nodes", &ForceModel::num_nodes)
      .def(
          "internal_forces",
          [](ForceModel& self, const PointsIn& x) {
            const Nodes X = checked_positions(self, x);
            Nodes f = Nodes::Zero(3, X.cols());
            self.add_forces(X, f);
            return Eigen::MatrixXd(f.transpose());
          },
          py::arg("positions"), "Internal elastic forces (n, 3) at positions (n, 3).")
      .def(
          "energy", [](ForceModel& self, const PointsIn& x) { return self.energy(checked_positions(self, x)); },
          py::arg("positions"))
      .def(
          "stiffness_csr",
          [](ForceModel& self, const PointsIn& x) {
            return stiffness_csr(self, checked_positions(self, x), StiffnessKind::Model);
          },
          py::arg("positions"),
          "Stiffness (the one implicit steps use) at positions as a CSR triple (data, indices, indptr).")
      .def(
          "tangent_csr",
          [](ForceModel& self, const PointsIn& x) {
            return stiffness_csr(self, checked_positions(self, x), StiffnessKind::Tangent);
          },
          py::arg("positions"), "Exact tangent -df/dx at positions as a CSR triple.")
      .def(
          "geometric_stiffness_csr",
          [](ForceModel& self, const PointsIn& x) {
            return stiffness_csr(self, checked_positions(self, x), StiffnessKind::Geometric);
          },
          py::arg("positions"), "Initial-stress stiffness K_sigma at positions (n, 3) as a CSR triple.")
      .def(
          "mass_csr", [](ForceModel& self, bool lumped) { return to_csr(self.mass_matrix(lumped)); },
          py::arg("lumped"));

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
             s.validate();
             return s;
           }),
           py::arg("max_iterations") = kPCG.max_iterations, py::arg("tolerance") = kPCG.tolerance,
           py::arg("warm_start") = kPCG.warm_start,
           py::arg("preconditioner") = std::string(preconditioner_name(kPCG.preconditioner)),
           "Settings of the capped PCG solver; the defaults are corotate's default solver (tolerance 0: "
           "the preconditioner's default, 2e-2 for two_level and 1e-2 for the others).")
      .def_readonly("max_iterations", &PCGSettings::max_iterations)
      .def_readonly("tolerance", &PCGSettings::tolerance)
      .def_readonly("warm_start", &PCGSettings::warm_start)
      .def_property_readonly("preconditioner",
                             [](const PCGSettings& s) { return preconditioner_name(s.preconditioner); });

  m.def(
      "solve_linear",
      [](const BlockSparseMatrix& A, const Vec& b, const std::optional<Vec>& x0, const std::string& solver,
         const PCGSettings& pcg, const std::optional<PointsIn>& geometry) {
        if (b.size() != A.num_dofs()) throw InvalidInput("right-hand side length does not match the matrix");
        // Both solvers read one triangle only (CG's product, the Cholesky factor); a sum of
        // symmetric matrices formed elsewhere may differ from its transpose by round-off.
        if (!A.is_symmetric(1e-12))
          throw InvalidInput(
              "solve_linear needs a symmetric matrix (A[i, j] == A[j, i] to 1e-12 of the largest entry)");
        Vec x = x0 ? *x0 : Vec::Zero(b.size());
        if (x.size() != b.size()) throw InvalidInput("initial guess length does not match the matrix");
        auto s = make_solver(solver, pcg);
        if (geometry) s->set_geometry(nodes_from(*geometry, "geometry"));
        const SolveStats stats = s->solve(A, b, x);
        return py::make_tuple(x, solve_stats_dict(stats));
      },
      py::arg("A"), py::arg("b"), py::arg("x0") = py::none(), py::arg("solver") = "pcg", py::arg("pcg") = PCGSettings{},
      py::arg("geometry") = py::none(),
      "Solve A x = b (A symmetric) with 'pcg' (settings pcg, initial guess x0) or 'direct'. geometry: (n, 3) node\n"
      "positions, needed by the two_level preconditioner. Returns (x, stats).");

  bind_simulation(m);  // simulation_bindings.cpp
  bind_contact(m);  // contact_bindings.cpp: after Simulation, which it extends
  bind_feedback(m);  // feedback_bindings.cpp
  bind_modal(m);  // modal_bindings.cpp
  bind_floating_frame(m);  // floating_frame_bindings.cpp
  bind_embedding(m);  // embedding_bindings.cpp
  bind_cell_types(m);  // cell_type_bindings.cpp
  bind_meshes(m);  // meshes_bindings.cpp
  bind_mass_spring(m);  // after ForceModel, which MassSpring derives from
  bind_hyperelastic(m);  // after ForceModel, which it returns
}
