// pybind11 glue for haptic feedback (corotate._core.HapticFeedback). Nothing but conversions.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "conversions.hpp"
#include "corotate/feedback/haptic_feedback.hpp"
#include "corotate/feedback/tool_feedback.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

void bind_feedback(py::module_& m) {
  py::class_<ToolFeedback>(m, "ToolFeedback")
      .def(py::init<std::shared_ptr<Obstacle>>(), py::arg("tool"))
      .def("update", &ToolFeedback::update, py::arg("simulation"),
           "After a body step: the force on the tool and the secant stiffness (feedback/tool_feedback.hpp).")
      .def(
          "query",
          [](const ToolFeedback& self, const Vec3& position) {
            ToolFeedback::Feedback f;
            {
              py::gil_scoped_release release;
              f = self.query(position);
            }
            return py::make_tuple(f.force, f.stiffness);
          },
          py::arg("position"), "(force on the tool (3,), dF/dp (3, 3)) at the tool position (3,).")
      .def_property_readonly("force", &ToolFeedback::force)
      .def_property_readonly("position", &ToolFeedback::position)
      .def_property_readonly("touching", &ToolFeedback::touching);
  m.def("feedback_method_names", &feedback_method_names, "Every feedback method name.");
  py::class_<HapticFeedback>(m, "HapticFeedback")
      .def(py::init([](const std::string& cell_type, const PointsIn& points, const CellsIn& cells,
                       const RegionMaterials& material, const std::vector<Index>& tool, const std::string& method,
                       double thickness) {
             return std::make_unique<HapticFeedback>(cell_type, nodes_from(points, "points"), cells_from(cells),
                                                     material, tool, feedback_method_from_name(method),
                                                     ModelOptions{thickness, false});
           }),
           py::arg("cell_type"), py::arg("points"), py::arg("cells"), py::arg("material"), py::arg("tool"),
           py::arg("method"), py::arg("thickness") = ModelOptions{}.thickness,
           "Force feedback at the tool nodes from the elements that touch them (see feedback/haptic_feedback.hpp).")
      .def(
          "query",
          [](HapticFeedback& self, const PointsIn& positions) {
            const Nodes x = nodes_from(positions, "positions");
            Nodes forces;
            Eigen::MatrixXd stiffness;
            {
              py::gil_scoped_release release;
              self.query(x, forces, stiffness);
            }
            return py::make_tuple(Eigen::MatrixXd(forces.transpose()), stiffness);
          },
          py::arg("positions"),
          "(forces (k, 3): the force the body exerts on each tool node, stiffness (3k, 3k): dF/dx) at positions (n, "
          "3).")
      .def_property_readonly("tool", &HapticFeedback::tool)
      .def_property_readonly("num_elements", &HapticFeedback::num_elements)
      .def_property_readonly(
          "method", [](const HapticFeedback& f) { return feedback_method_names()[static_cast<int>(f.method())]; });
}
