// pybind11 glue for the hyperelastic constitutive laws on their own (for tests). Nothing
// but conversions; InvalidInput becomes ValueError.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/material.hpp"
#include "corotate/materials/law_parameters.hpp"
#include "corotate/models/model_factory.hpp"
#include "corotate/models/registry.hpp"

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
  m.def(
      "constitutive_law",
      [](const std::string& law, const Mat3& F, const Material& material) {
        py::tuple result;
        const bool known = visit_by_name(HyperelasticLaws{}, law, [&](auto tag) {
          using L = typename decltype(tag)::type;
          result = evaluate_law(law_of_material<L>(material), F);
        });
        if (!known) {
          check_renamed_model(law);
          std::string choices;
          for (const auto& name : names_of(HyperelasticLaws{})) choices += (choices.empty() ? "'" : ", '") + name + "'";
          throw InvalidInput("unknown constitutive law '" + law + "' (choose " + choices + ")");
        }
        return result;
      },
      py::arg("law"), py::arg("F"), py::arg("material"),
      "(W, P, dP/dF) of a law at the 3x3 deformation gradient F: energy density, first Piola-Kirchhoff\n"
      "stress (3x3) and its derivative (9x9, column-major vec: index i + 3j for F[i, j]).");
}
