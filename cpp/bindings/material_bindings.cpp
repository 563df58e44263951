// pybind11 glue for materials given in a law's own parameters and for bodies of several
// materials (corotate._core.RegionMaterials). Nothing but conversions.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <map>

#include "conversions.hpp"
#include "corotate/region_materials.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

void bind_materials(py::module_& m) {
  m.def(
      "material_of_law",
      [](const std::string& law, const std::map<std::string, double>& parameters, double density) {
        return material_of_law(law, {parameters.begin(), parameters.end()}, density);
      },
      py::arg("law"), py::arg("parameters"), py::arg("density"),
      "A Material given in a law's own parameters ({name: value}); its youngs_modulus and poisson_ratio are the\n"
      "law's small-strain moduli. ValueError naming an unknown, missing or out-of-range parameter.");
  m.def(
      "law_parameters",
      [] {
        py::dict out;
        for (const LawDeclaration& d : law_declarations()) out[py::str(d.law)] = d.parameters;
        return out;
      },
      "{law: [(parameter, meaning), ...]} for every law with parameters of its own, in the order it declares them.");

  py::class_<RegionMaterials>(m, "RegionMaterials")
      .def(py::init([](const std::vector<Material>& materials, const CellsIn& cell_regions) {
             if (cell_regions.ndim() != 1) throw InvalidInput("regions must have shape (m,): one id per cell");
             std::vector<int> regions(cell_regions.size());
             for (py::ssize_t e = 0; e < cell_regions.size(); ++e) {
               const long long r = cell_regions.data()[e];
               if (r < std::numeric_limits<int>::min() || r > std::numeric_limits<int>::max())
                 throw InvalidInput("cell " + std::to_string(e) + " has region id " + std::to_string(r) +
                                    ", out of range");
               regions[e] = static_cast<int>(r);  // checked against the materials by the model
             }
             return RegionMaterials(materials, regions);
           }),
           py::arg("materials"), py::arg("cell_regions"),
           "Materials by region id (0, 1, ...) and the (m,) region id of each cell.")
      .def(py::init<const Material&>(), py::arg("material"), "One material for every cell.")
      .def_readonly("materials", &RegionMaterials::materials);
  py::implicitly_convertible<Material, RegionMaterials>();  // through the constructor above
}
