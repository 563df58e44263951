// pybind11 glue for the modal (reduced) body: the polynomial modal forces, the modal
// integrator and the per-frame basis products. Nothing but conversions and shape checks.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>

#include "conversions.hpp"
#include "corotate/modal/modal_basis.hpp"
#include "corotate/modal/modal_integrator.hpp"
#include "corotate/modal/partial_rotation.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

namespace {

using MatIn = Eigen::MatrixXd;
using DoubleArray = py::array_t<double, py::array::c_style>;
using NodeArray = py::array_t<long long, py::array::c_style | py::array::forcecast>;

// A 1-D view of a vector owned by `owner` (writable, no copy).
py::array vector_view(Vec& x, py::handle owner) {
  return DoubleArray({x.size()}, {Index(sizeof(double))}, x.data(), owner);
}

void assign(Vec& dst, const Vec& src, const char* what) {
  if (src.size() != dst.size())
    throw InvalidInput(std::string(what) + " must have " + std::to_string(dst.size()) + " entries");
  if (!src.allFinite()) throw InvalidInput(std::string(what) + " must be finite");
  dst = src;
}

// The basis as a read-only map: (3n, r) C-contiguous float64, no copy.
BasisMap basis_map(const py::array& basis) {
  if (!py::isinstance<DoubleArray>(basis) || !(basis.flags() & py::array::c_style) || basis.ndim() != 2 ||
      basis.shape(0) % 3 != 0 || basis.shape(0) == 0 || basis.shape(1) == 0)
    throw InvalidInput("basis must be a C-contiguous float64 array of shape (3n, r)");
  return BasisMap(static_cast<const double*>(basis.data()), basis.shape(0), basis.shape(1));
}

double* writable_nodes_buffer(py::array& out, Index count, const char* what) {
  if (!py::isinstance<DoubleArray>(out) || !(out.flags() & py::array::c_style) || !out.writeable() || out.ndim() != 2 ||
      out.shape(0) != count || out.shape(1) != 3)
    throw InvalidInput(std::string(what) + " must be a writable C-contiguous float64 array of shape (" +
                       std::to_string(count) + ", 3)");
  return static_cast<double*>(out.mutable_data());
}

Index checked_domain(const PartialRotation& s, Index d) {
  if (d < 0 || d >= s.n_domains())
    throw InvalidInput("domain " + std::to_string(d) + " is out of range [0, " + std::to_string(s.n_domains()) + ")");
  return d;
}

}  // namespace

void bind_modal(py::module_& m) {
  py::class_<ModalIntegrator>(m, "ModalIntegrator")
      .def(py::init([](const MatIn& stiffness, const MatIn& quadratic, const MatIn& cubic, double dt, double alpha,
                       double beta) {
             return ModalIntegrator(ModalForces(stiffness, quadratic, cubic), ModalStepSettings{dt, alpha, beta});
           }),
           py::arg("stiffness"), py::arg("quadratic"), py::arg("cubic"), py::arg("dt"), py::arg("mass_damping"),
           py::arg("stiffness_damping"))
      .def_property_readonly("size", &ModalIntegrator::size)
      .def_property_readonly("q", [](py::object self) { return vector_view(self.cast<ModalIntegrator&>().q, self); })
      .def_property_readonly("v", [](py::object self) { return vector_view(self.cast<ModalIntegrator&>().v, self); })
      .def_property_readonly("p", [](py::object self) { return vector_view(self.cast<ModalIntegrator&>().p, self); })
      .def("set_q", [](ModalIntegrator& s, const Vec& x) { assign(s.q, x, "modal coordinates q"); })
      .def("set_v", [](ModalIntegrator& s, const Vec& x) { assign(s.v, x, "modal velocities"); })
      .def("set_p", [](ModalIntegrator& s, const Vec& x) { assign(s.p, x, "modal forces"); })
      .def_readwrite("time", &ModalIntegrator::time)
      .def_property(
          "settings",
          [](const ModalIntegrator& s) {
            return py::make_tuple(s.settings().dt, s.settings().mass_damping, s.settings().stiffness_damping);
          },
          [](ModalIntegrator& s, const py::tuple& t) {
            s.set_settings(ModalStepSettings{t[0].cast<double>(), t[1].cast<double>(), t[2].cast<double>()});
          })
      .def("set_load_stiffness", &ModalIntegrator::set_load_stiffness, py::arg("extra"))
      .def("step", &ModalIntegrator::step, py::arg("n"), py::call_guard<py::gil_scoped_release>())
      .def("solve_static", &ModalIntegrator::solve_static, py::arg("load_steps"), py::arg("tolerance"),
           py::arg("max_iterations"))
      .def("reset", &ModalIntegrator::reset)
      .def("internal_forces", [](ModalIntegrator& s) { return Vec(s.internal_forces()); })
      .def(
          "evaluate",
          [](ModalIntegrator& s, const Vec& q) {
            Vec f;
            Eigen::MatrixXd T;
            s.forces().evaluate(q, f, &T);
            return py::make_tuple(f, T);
          },
          py::arg("q"))
      .def(
          "energy", [](ModalIntegrator& s, const Vec& q) { return s.forces().energy(q); }, py::arg("q"))
      .def_property_readonly("stiffness", [](ModalIntegrator& s) { return Eigen::MatrixXd(s.forces().stiffness()); });

  py::class_<PartialRotation>(m, "PartialRotation")
      .def(py::init([](const PointsIn& rest, const std::vector<std::vector<long long>>& representative,
                       const NodeArray& blended_nodes, const DoubleArray& weights) {
             if (rest.ndim() != 2 || rest.shape(1) != 3) throw InvalidInput("rest positions must have shape (n, 3)");
             if (weights.ndim() != 2 || weights.shape(0) != blended_nodes.size() ||
                 weights.shape(1) != py::ssize_t(representative.size()))
               throw InvalidInput("weights must have shape (len(blended_nodes), number of domains)");
             return PartialRotation(
                 rest.data(), rest.shape(0), representative,
                 std::vector<long long>(blended_nodes.data(), blended_nodes.data() + blended_nodes.size()),
                 weights.data());
           }),
           py::arg("rest"), py::arg("representative"), py::arg("blended_nodes"), py::arg("weights"))
      .def_property_readonly("n_nodes", &PartialRotation::n_nodes)
      .def_property_readonly("n_domains", &PartialRotation::n_domains)
      .def_property_readonly("representative_nodes", [](const PartialRotation& s) { return s.representative_nodes(); })
      .def(
          "rotation", [](const PartialRotation& s, Index d) { return Mat3(s.rotation(checked_domain(s, d))); },
          py::arg("domain"))
      .def(
          "rotation_vector",
          [](const PartialRotation& s, Index d) { return Vec3(s.rotation_vector(checked_domain(s, d))); },
          py::arg("domain"));

  m.def(
      "recover_displacements",
      [](const py::array& basis, const VecRef& q, const std::optional<NodeArray>& nodes, py::array& out,
         std::optional<std::reference_wrapper<PartialRotation>> rotation_arg) {
        PartialRotation* rotation = rotation_arg ? &rotation_arg->get() : nullptr;
        // float64 basis: the exact recovery; float32: a half-size copy for speed. q by reference
        // (ModalBody passes the core's own contiguous q): a frame allocates nothing.
        const bool single = py::isinstance<py::array_t<float, py::array::c_style>>(basis) && basis.ndim() == 2 &&
                            (basis.flags() & py::array::c_style) && basis.shape(0) % 3 == 0 && basis.shape(1) > 0;
        const BasisMap B = single ? BasisMap(nullptr, basis.shape(0), basis.shape(1)) : basis_map(basis);
        if (q.size() != B.cols()) throw InvalidInput("q must have one entry per basis vector");
        if (!q.allFinite()) throw InvalidInput("q must be finite");
        const Index n = B.rows() / 3;
        if (rotation && rotation->n_nodes() != n)
          throw InvalidInput("the partial rotation is set up for " + std::to_string(rotation->n_nodes()) +
                             " nodes, the basis has " + std::to_string(n));
        const long long* idx = nodes ? nodes->data() : nullptr;
        const Index count = nodes ? Index(nodes->size()) : n;
        if (idx) check_node_indices(idx, count, n);
        double* o = writable_nodes_buffer(out, count, "out");
        const float* f = single ? static_cast<const float*>(basis.data()) : nullptr;
        // Without a rotation only the caller's out is written: the GIL is released. A
        // PartialRotation keeps its fit in itself and may be shared by several bodies, so its
        // recoveries keep the GIL and run one at a time.
        std::optional<py::gil_scoped_release> release;
        if (!rotation) release.emplace();
        auto recover = [&](const long long* which, Index how_many, double* into) {
          if (single) recover_displacements(f, B.rows(), B.cols(), q, which, how_many, into);
          else recover_displacements(B, q, which, how_many, into);
        };
        recover(idx, count, o);
        if (rotation) {
          const auto& points = rotation->representative_nodes();
          recover(points.data(), Index(points.size()), rotation->representative_buffer());
          rotation->fit(rotation->representative_buffer());
          rotation->rotate(idx, count, o);
        }
      },
      py::arg("basis"), py::arg("q"), py::arg("nodes"), py::arg("out"), py::arg("rotation") = py::none(),
      "out[k] = displacement of nodes[k] (all nodes when nodes is None) for modal coordinates q; basis (3n, r) "
      "C-contiguous float64 or float32. With a PartialRotation, each domain's displacements are then turned by "
      "its rotation (fitted to its representative points' displacements, recovered from the same basis).");
  m.def(
      "least_squares_rotation",
      [](const PointsIn& rest, const PointsIn& moved) {
        if (rest.ndim() != 2 || rest.shape(1) != 3 || moved.ndim() != 2 || moved.shape(0) != rest.shape(0) ||
            moved.shape(1) != 3)
          throw InvalidInput("rest and moved points must both have shape (m, 3)");
        const Nodes a = nodes_from(rest, "rest points"), b = nodes_from(moved, "moved points");
        if (!a.allFinite() || !b.allFinite()) throw InvalidInput("points must be finite");
        const Mat3 covariance = (a.colwise() - a.rowwise().mean()) * (b.colwise() - b.rowwise().mean()).transpose();
        return least_squares_rotation(covariance);
      },
      py::arg("rest"), py::arg("moved"),
      "The proper rotation R minimising sum |R (p_i - p_mean) - (x_i - x_mean)|^2 (Kabsch).");
  m.def(
      "rotate_displacements",
      [](PartialRotation& rotation, const PointsIn& u, py::array& out) {
        const Index n = rotation.n_nodes();
        if (u.ndim() != 2 || u.shape(0) != n || u.shape(1) != 3)
          throw InvalidInput("displacements must have shape (" + std::to_string(n) + ", 3)");
        for (py::ssize_t k = 0; k < u.size(); ++k)
          if (!std::isfinite(u.data()[k])) throw InvalidInput("displacements must be finite");
        double* o = writable_nodes_buffer(out, n, "out");
        const auto& points = rotation.representative_nodes();
        for (std::size_t i = 0; i < points.size(); ++i)
          for (int a = 0; a < 3; ++a) rotation.representative_buffer()[3 * i + a] = u.data()[3 * points[i] + a];
        rotation.fit(rotation.representative_buffer());
        if (o != u.data()) std::copy(u.data(), u.data() + 3 * n, o);
        rotation.rotate(nullptr, n, o);
      },
      py::arg("rotation"), py::arg("displacements"), py::arg("out"),
      "out = displacements (n, 3) with each domain's part turned by its rotation (fitted to the representative "
      "points of these displacements).");
  m.def(
      "project_nodal_forces",
      [](const py::array& basis, const NodeArray& nodes, const PointsIn& forces, py::array& p) {
        const BasisMap B = basis_map(basis);
        if (forces.ndim() != 2 || forces.shape(1) != 3 || forces.shape(0) != nodes.size())
          throw InvalidInput("forces must have shape (len(nodes), 3)");
        check_node_indices(nodes.data(), nodes.size(), B.rows() / 3);
        for (py::ssize_t k = 0; k < forces.size(); ++k)
          if (!std::isfinite(forces.data()[k]))
            throw InvalidInput("force on node " + std::to_string(nodes.data()[k / 3]) + " is not finite");
        if (!py::isinstance<DoubleArray>(p) || p.ndim() != 1 || p.shape(0) != B.cols() || !p.writeable())
          throw InvalidInput("p must be a writable float64 vector with one entry per basis vector");
        if (!(p.flags() & py::array::c_style)) throw InvalidInput("p must be contiguous");
        project_nodal_forces(B, nodes.data(), nodes.size(), forces.data(), static_cast<double*>(p.mutable_data()));
      },
      py::arg("basis"), py::arg("nodes"), py::arg("forces"), py::arg("p"),
      "p = sum over nodes of basis[rows of node]^T forces[k] (only the loaded nodes' rows are read).");
}
