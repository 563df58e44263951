// pybind11 glue for the hyperelastic models (corotate._core): a model factory with the
// options only these models take (sheet thickness, PSD projection), the initial-stress
// stiffness, and the constitutive laws on their own (for tests). Nothing but conversions;
// InvalidInput becomes ValueError.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/materials/fixed_corotated.hpp"
#include "corotate/materials/stable_neo_hookean.hpp"
#include "corotate/materials/stvk.hpp"
#include "corotate/models/geometric_stiffness.hpp"
#include "corotate/models/model_factory.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {


template <class Law>
py::tuple evaluate_law(const Law& law, const Mat3& F) {
  return py::make_tuple(law.energy(F), Mat3(law.stress(F)), Eigen::MatrixXd(law.tangent(F)));
}

}  // namespace

void bind_hyperelastic(py::module_& m) {
  m.def("make_force_model", [](const std::string& model, const std::string& cell_type, const PointsIn& points,
                               const CellsIn& cells, const Material& material, double thickness, bool project_psd) {
    return make_model(model, cell_type, nodes_from(points, "points"), cells_from(cells), material,
                      ModelOptions{thickness, project_psd});
  }, py::arg("model"), py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"),
        py::arg("thickness") = 1.0, py::arg("project_psd") = false,
        "ForceModel by name with the options of the hyperelastic models: thickness of triangle sheets [m],\n"
        "project_psd (clamp each element stiffness to positive semi-definite).");

  m.def("geometric_stiffness_csr", [](ForceModel& model, const PointsIn& positions) {
    const auto* g = dynamic_cast<const GeometricStiffness*>(&model);
    if (!g)
      throw InvalidInput(std::string("the '") + model.name() +
                         "' model has no separate geometric stiffness (use 'stvk', 'neohookean' or 'corotated')");
    const Nodes x = nodes_from(positions, "positions");
    if (x.cols() != model.num_nodes()) throw InvalidInput("positions must have one row per node");
    if (Index i = first_non_finite_node(x); i >= 0) throw InvalidInput("position of node " + std::to_string(i) + " is not finite");
    BlockSparseMatrix K = model.pattern();
    K.set_zero();
    g->add_geometric_stiffness(x, 1.0, K);
    return to_csr(K);
  }, py::arg("model"), py::arg("positions"),
        "Initial-stress stiffness K_sigma at positions (n, 3) as a CSR triple (data, indices, indptr).");

  m.def("constitutive_law", [](const std::string& law, const Mat3& F, const Material& material) {
    const double lambda = material.lame_lambda(), mu = material.lame_mu();
    if (law == StVK::name) return evaluate_law(StVK{lambda, mu}, F);
    if (law == StableNeoHookean::name) return evaluate_law(StableNeoHookean{lambda, mu}, F);
    if (law == FixedCorotated::name) return evaluate_law(FixedCorotated{lambda, mu}, F);
    throw InvalidInput("unknown constitutive law '" + law + "' (choose 'stvk', 'neohookean' or 'corotated')");
  }, py::arg("law"), py::arg("F"), py::arg("material"),
        "(W, P, dP/dF) of a law at the 3x3 deformation gradient F: energy density, first Piola-Kirchhoff\n"
        "stress (3x3) and its derivative (9x9, column-major vec: index i + 3j for F[i, j]).");
}
