// pybind11 glue for the floating-frame modal body (modal/floating_frame_body.hpp): the body
// and its state in one object, stepped without the GIL. Nothing but conversions and checks;
// corotate.modal.FloatingBody is the user's class.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "conversions.hpp"
#include "corotate/modal/floating_frame_body.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

struct FloatingFrame {
  FloatingFrameBody body;
  FloatingFrameState state;
  double time = 0.0;
};

FrameSupport support_from(const std::string& name) {
  if (name == "free") return FrameSupport::Free;
  if (name == "spherical") return FrameSupport::Spherical;
  if (name == "revolute") return FrameSupport::Revolute;
  throw InvalidInput("support must be 'free', 'spherical' or 'revolute', got '" + name + "'");
}

LoadFrame load_frame_from(const std::string& name) {
  if (name == "world") return LoadFrame::World;
  if (name == "body") return LoadFrame::Body;
  throw InvalidInput("a load's frame must be 'world' or 'body', got '" + name + "'");
}

// (iterations, residual): plain C++ values, converted once the GIL is held again.
std::pair<int, double> stats_pair(const FloatingFrameStepStats& s) { return {s.iterations, s.residual}; }

}  // namespace

void bind_floating_frame(py::module_& m) {
  py::class_<FloatingFrame>(m, "FloatingFrame")
      .def(py::init([](const PointsIn& rest, const Eigen::SparseMatrix<double>& node_mass, const Eigen::MatrixXd& basis,
                       const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& damping) {
             FloatingFrameBody body(FloatingFrameInertia(nodes_from(rest, "rest positions"), node_mass, basis),
                                    stiffness, damping);
             FloatingFrameState state = body.rest_state();
             return FloatingFrame{std::move(body), std::move(state), 0.0};
           }),
           py::arg("rest"), py::arg("node_mass"), py::arg("basis"), py::arg("stiffness"), py::arg("damping"))
      .def_property_readonly("n_modes", [](const FloatingFrame& f) { return f.body.inertia().num_modes(); })
      .def_property_readonly("mass", [](const FloatingFrame& f) { return f.body.inertia().mass(); })
      .def("set_gravity",
           [](FloatingFrame& f, const Vec3& g) {
             if (!g.allFinite()) throw InvalidInput("gravity must be finite");
             f.body.set_gravity(g);
           })
      .def(
          "set_support",
          [](FloatingFrame& f, const std::string& kind, const Vec3& axis) {
            f.body.set_support(support_from(kind), axis);
          },
          py::arg("kind"), py::arg("axis"))
      .def(
          "set_node_loads",
          [](FloatingFrame& f, const PointsIn& points, const Eigen::MatrixXd& rows, const PointsIn& forces,
             const std::string& frame) {
            f.body.set_node_loads(nodes_from(points, "load points"), rows, nodes_from(forces, "forces"),
                                  load_frame_from(frame));
          },
          py::arg("points"), py::arg("rows"), py::arg("forces"), py::arg("frame"))
      .def(
          "set_geometric_stiffness",
          [](FloatingFrame& f, const std::vector<Eigen::MatrixXd>& per_case) {
            f.body.set_geometric_stiffness(per_case);
          },
          py::arg("per_case"))
      .def_property_readonly("stiffening", [](const FloatingFrame& f) { return f.body.stiffening(); })
      // The state: copies out, checked copies in (a failed set changes nothing).
      .def_property_readonly("position", [](const FloatingFrame& f) { return f.state.position; })
      .def_property_readonly("rotation", [](const FloatingFrame& f) { return f.state.rotation; })
      .def_property_readonly("zeta", [](const FloatingFrame& f) { return f.state.zeta; })
      .def_property_readonly("velocity", [](const FloatingFrame& f) { return f.state.velocity; })
      .def_readwrite("time", &FloatingFrame::time)
      .def(
          "set_state",
          [](FloatingFrame& f, const Vec3& position, const Mat3& rotation, const Vec& zeta, const Vec& velocity) {
            FloatingFrameState s{position, rotation, zeta, velocity};
            f.body.energy(s);  // checks sizes, finiteness and the rotation
            f.state = std::move(s);
          },
          py::arg("position"), py::arg("rotation"), py::arg("zeta"), py::arg("velocity"))
      .def(
          "step",
          [](FloatingFrame& f, double h, int n) {
            const auto stats = f.body.advance(f.state, h, n);
            f.time += n * h;
            return stats_pair(stats);
          },
          py::arg("h"), py::arg("n"), py::call_guard<py::gil_scoped_release>(),
          "n steps of h; on failure the state is as before the call. Returns (iterations, residual) of the last.")
      .def(
          "step_prescribed",
          [](FloatingFrame& f, double h, const Vec3& position, const Mat3& rotation, const Vec3& velocity,
             const Vec3& angular_velocity) {
            const FramePose end{position, rotation, velocity, angular_velocity};
            const auto stats = f.body.step_prescribed(f.state, h, end);
            f.time += h;
            return stats_pair(stats);
          },
          py::arg("h"), py::arg("position"), py::arg("rotation"), py::arg("velocity"), py::arg("angular_velocity"),
          "One step of h to the frame pose given (velocities in the frame); only the modes are solved for.")
      .def_property_readonly("energy", [](const FloatingFrame& f) { return f.body.energy(f.state); })
      .def_property_readonly("linear_momentum", [](const FloatingFrame& f) { return f.body.linear_momentum(f.state); })
      .def_property_readonly("angular_momentum",
                             [](const FloatingFrame& f) { return f.body.angular_momentum(f.state); })
      .def(
          "mass_matrix",
          [](const FloatingFrame& f, const Vec& zeta) {
            if (zeta.size() != f.body.inertia().num_modes() || !zeta.allFinite())
              throw InvalidInput("zeta must be " + std::to_string(f.body.inertia().num_modes()) + " finite numbers");
            Eigen::MatrixXd M;
            f.body.inertia().mass_matrix(zeta, M);
            return M;
          },
          py::arg("zeta"));
  m.def("inertial_load_coefficients", &inertial_load_coefficients, py::arg("omega"), py::arg("alpha"),
        py::arg("acceleration_minus_gravity"),
        "The twelve coefficients of the unit inertial load cases (modal/inertial_load_cases.hpp).");
}
