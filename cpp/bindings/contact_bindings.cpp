// pybind11 glue for contact: the obstacles (corotate._core.Plane and the analytic shapes),
// the contact settings, and Simulation's contact members. Nothing but conversions.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>

#include "conversions.hpp"
#include "corotate/contact/obstacle.hpp"
#include "corotate/contact/triangle_mesh.hpp"
#include "corotate/simulation.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

void bind_contact(py::module_& m) {
  py::class_<Obstacle, std::shared_ptr<Obstacle>>(m, "Obstacle")
      .def_property_readonly("rotation", [](const Obstacle& o) { return Mat3(o.pose().rotation); })
      .def_property_readonly("translation", [](const Obstacle& o) { return Vec3(o.pose().translation); })
      .def(
          "set_pose",
          [](Obstacle& o, const Mat3& rotation, const Vec3& translation) {
            Pose p;
            p.rotation = rotation;
            p.translation = translation;
            o.set_pose(p);
          },
          py::arg("rotation"), py::arg("translation"), "Place the shape: x_world = rotation x_local + translation.")
      .def_property_readonly("version", &Obstacle::version)
      .def(
          "distance",
          [](const Obstacle& o, const PointsIn& points) {
            const Nodes p = nodes_from(points, "points");
            const Pose pose = o.pose();
            Eigen::VectorXd d(p.cols());
            Eigen::MatrixXd normals(p.cols(), 3);
            Vec3 n;
            for (Index i = 0; i < p.cols(); ++i) {
              d[i] = o.local_distance(pose.to_local(p.col(i)), n);
              normals.row(i) = (pose.rotation * n).transpose();
            }
            return py::make_tuple(d, normals);
          },
          py::arg("points"), "(signed distances (m,), outward unit normals (m, 3)) of world points (m, 3).")
      .def("__repr__", &Obstacle::describe);
  py::class_<HalfSpace, Obstacle, std::shared_ptr<HalfSpace>>(m, "HalfSpace").def(py::init<>());
  py::class_<Sphere, Obstacle, std::shared_ptr<Sphere>>(m, "Sphere")
      .def(py::init<double>(), py::arg("radius"))
      .def_property_readonly("radius", &Sphere::radius);
  py::class_<Box, Obstacle, std::shared_ptr<Box>>(m, "Box").def(py::init<const Vec3&>(), py::arg("half_extents"));
  py::class_<Capsule, Obstacle, std::shared_ptr<Capsule>>(m, "Capsule")
      .def(py::init<double, double>(), py::arg("radius"), py::arg("half_length"));
  py::class_<Cylinder, Obstacle, std::shared_ptr<Cylinder>>(m, "Cylinder")
      .def(py::init<double, double>(), py::arg("radius"), py::arg("half_length"));

  py::class_<TriangleMesh, Obstacle, std::shared_ptr<TriangleMesh>>(m, "TriangleMesh")
      .def(py::init([](const PointsIn& vertices, const CellsIn& triangles) {
             const Connectivity c = cells_from(triangles);
             if (c.cols() != 3) throw InvalidInput("triangles must have shape (m, 3)");
             Triangles t(c.rows());
             for (Index k = 0; k < c.rows(); ++k) t[k] = {c(k, 0), c(k, 1), c(k, 2)};
             return std::make_shared<TriangleMesh>(nodes_from(vertices, "vertices"), t);
           }),
           py::arg("vertices"), py::arg("triangles"))
      .def(
          "set_vertices",
          [](TriangleMesh& mesh, const PointsIn& vertices, std::optional<PointsIn> velocities) {
            const Nodes x = nodes_from(vertices, "vertices");
            if (!velocities) return mesh.set_vertices(x);
            const Nodes v = nodes_from(*velocities, "velocities");
            mesh.set_vertices(x, &v);
          },
          py::arg("vertices"), py::arg("velocities") = py::none(),
          "Move the vertices (own frame), with their velocities (zero if None).")
      .def_property_readonly("vertices",
                             [](const TriangleMesh& mesh) { return Eigen::MatrixXd(mesh.vertices().transpose()); })
      .def_property_readonly("triangles",
                             [](const TriangleMesh& mesh) {
                               const Triangles t = mesh.triangles();
                               Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> out(t.size(), 3);
                               for (size_t k = 0; k < t.size(); ++k) out.row(k) << t[k][0], t[k][1], t[k][2];
                               return out;
                             })
      .def(
          "distribute",
          [](const TriangleMesh& mesh, const PointsIn& points, const PointsIn& forces) {
            return Eigen::MatrixXd(
                mesh.distribute(nodes_from(points, "points"), nodes_from(forces, "forces")).transpose());
          },
          py::arg("points"), py::arg("forces"),
          "Spread point forces (m, 3) at points (m, 3) (own frame) onto the vertices (n, 3) by barycentric weights.");

  py::class_<ContactSettings>(m, "ContactSettings")
      .def(py::init([](double stiffness_scale, double friction_velocity, bool edge_contact) {
             ContactSettings s;
             s.stiffness_scale = stiffness_scale;
             s.friction_velocity = friction_velocity;
             s.edge_contact = edge_contact;
             s.validate();
             return s;
           }),
           py::arg("stiffness_scale") = ContactSettings{}.stiffness_scale,
           py::arg("friction_velocity") = ContactSettings{}.friction_velocity,
           py::arg("edge_contact") = ContactSettings{}.edge_contact)
      .def_readonly("stiffness_scale", &ContactSettings::stiffness_scale)
      .def_readonly("friction_velocity", &ContactSettings::friction_velocity)
      .def_readonly("edge_contact", &ContactSettings::edge_contact);

  auto sim = py::reinterpret_borrow<py::class_<Simulation>>(m.attr("Simulation"));
  sim.def("add_obstacle", &Simulation::add_obstacle, py::arg("obstacle"), py::arg("friction") = 0.0)
      .def("remove_obstacle", &Simulation::remove_obstacle, py::arg("obstacle"))
      .def("set_friction", &Simulation::set_friction, py::arg("obstacle"), py::arg("friction"))
      .def_property_readonly("obstacles",
                             [](const Simulation& s) {
                               const Simulation::Claim claim(s, "reading the obstacles");
                               py::list out;
                               for (const ObstacleLink& link : s.obstacles())
                                 out.append(py::make_tuple(link.obstacle, link.friction));
                               return out;
                             })
      .def_property(
          "contact_nodes", [](const Simulation& s) { return s.contacts().nodes(); }, &Simulation::set_contact_nodes)
      .def(
          "set_contact_points",
          [](Simulation& s, const CellsIn& nodes,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& weights) {
            const Connectivity n = cells_from(nodes);
            if (weights.ndim() != 2 || weights.shape(0) != n.rows() || weights.shape(1) != n.cols())
              throw InvalidInput("contact point weights must have the shape of their nodes (m, k)");
            ContactPoints points;
            points.per_point = static_cast<int>(n.cols());
            const auto w = weights.unchecked<2>();
            for (Index p = 0; p < n.rows(); ++p)
              for (Index k = 0; k < n.cols(); ++k) {
                points.nodes.push_back(n(p, k));
                points.weights.push_back(w(p, k));
              }
            s.set_contact_points(std::move(points));
          },
          py::arg("nodes"), py::arg("weights"),
          "Contact points instead of the nodes: point p is sum_k weights[p, k] x[nodes[p, k]] ((m, k) each).")
      .def_property_readonly("contact_points_set", [](const Simulation& s) { return !s.contacts().points().empty(); })
      .def_property(
          "contact_settings", [](const Simulation& s) { return s.contacts().settings(); },
          &Simulation::set_contact_settings)
      .def_property_readonly(
          "contacts",
          [](const Simulation& s) {
            const Simulation::Claim claim(s, "reading the contacts");
            const ContactSet& set = s.contacts();
            const auto& cs = set.contacts();
            const Index m = static_cast<Index>(cs.size());
            Eigen::Matrix<Index, Eigen::Dynamic, 1> nodes(m);
            Eigen::VectorXi obstacles(m), parts(m);
            Eigen::Matrix<bool, Eigen::Dynamic, 1> edges(m);
            Eigen::Matrix<Index, Eigen::Dynamic, 3, Eigen::RowMajor> partners(m, 3);
            Eigen::MatrixXd normals(m, 3), points(m, 3), forces(m, 3), weights(m, 3);
            Eigen::VectorXd multipliers(m), friction_limits(m);
            const bool committed = set.forces().cols() == m;
            for (Index k = 0; k < m; ++k) {
              nodes[k] = cs[k].node;
              obstacles[k] = cs[k].obstacle >= 0 ? cs[k].obstacle : -1;
              parts[k] = cs[k].obstacle < 0 ? -1 - cs[k].obstacle : -1;
              for (int j = 0; j < 3; ++j) partners(k, j) = cs[k].partners[j];
              edges[k] = cs[k].edge();
              // An edge's contact: the points' parameters s and t on the two edges.
              weights.row(k) = cs[k].edge() ? Eigen::RowVector3d(-cs[k].weights[0], cs[k].weights[2], 0.0)
                                            : Eigen::RowVector3d(cs[k].weights.transpose());
              normals.row(k) = cs[k].normal.transpose();
              points.row(k) = cs[k].point.transpose();
              forces.row(k) = committed ? Vec3(set.forces().col(k)) : Vec3(Vec3::Zero());
              multipliers[k] = cs[k].multiplier;
              friction_limits[k] = cs[k].friction_force;
            }
            py::dict d;
            d["nodes"] = nodes;
            d["obstacles"] = obstacles;
            d["parts"] = parts;
            d["partners"] = partners;
            d["edges"] = edges;
            d["weights"] = weights;
            d["normals"] = normals;
            d["points"] = points;
            d["forces"] = forces;
            d["multipliers"] = multipliers;
            d["friction_limits"] = friction_limits;
            return d;
          },
          "The last step's contacts: nodes, obstacle indices (-1 for a part), part indices (-1 for an obstacle), "
          "a part's triangle (partners, -1 for an obstacle) and the contact point's weights on it (an edge against "
          "an edge, edges True: nodes and partners[:, 0] the edge, partners[:, 1:] the other's, weights (s, t, 0) "
          "the points on them), the planes "
          "(normals, points), the force each exerted on its node at the step's end (m, 3), the normal multipliers "
          "carried to the next step and the friction limits mu N of the step (N: the multiplier carried into it).")
      .def(
          "set_part_contact",
          [](Simulation& s, const CellsIn& triangles, const std::vector<int>& part_of_node, double friction,
             bool self_contact) {
            const Connectivity c = cells_from(triangles);
            if (c.rows() > 0 && c.cols() != 3) throw InvalidInput("the surface triangles must have shape (m, 3)");
            Triangles t(c.rows());
            for (Index k = 0; k < c.rows(); ++k) t[k] = {c(k, 0), c(k, 1), c(k, 2)};
            s.set_part_contact(t, part_of_node, friction, self_contact);
          },
          py::arg("triangles"), py::arg("part_of_node"), py::arg("friction") = 0.0, py::arg("self_contact") = false,
          "Contact between the body's parts (and within each, self_contact): every part's outward boundary "
          "triangles (m, 3), each node's part.")
      .def("clear_part_contact", &Simulation::clear_part_contact)
      .def_property_readonly("part_contact", [](const Simulation& s) { return s.contacts().has_parts(); })
      .def_property_readonly("self_contact", [](const Simulation& s) { return s.contacts().has_self_contact(); })
      .def_property_readonly("part_friction", [](const Simulation& s) { return s.contacts().part_friction(); })
      .def(
          "contact_system",
          [](const Simulation& s, const PointsIn& positions) {
            const Simulation::Claim claim(s, "evaluating the contact potential");
            const Nodes y = nodes_from(positions, "positions");
            const Index n = s.num_nodes();
            if (y.cols() != n) throw InvalidInput("positions must have one row per node");
            if (n > 2000) throw InvalidInput("contact_system builds a dense Hessian: at most 2000 nodes");
            const ContactSet& set = s.contacts();
            Nodes f = Nodes::Zero(3, n);
            set.add_forces(y, f);
            Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(3 * n, 3 * n);
            for (const Contact& c : set.contacts()) {
              Mat3 h;
              set.force_of(c, set.relative(c, y), &h);
              const ContactSet::Stencil st = set.stencil(c);
              for (int a = 0; a < st.size; ++a)
                for (int b = 0; b < st.size; ++b)
                  hessian.block<3, 3>(3 * st.nodes[a], 3 * st.nodes[b]) += st.e[a] * st.e[b] * h;
            }
            return py::make_tuple(set.energy(y), Eigen::MatrixXd(f.transpose()), hessian);
          },
          py::arg("positions"),
          "The last step's contact potential at positions (n, 3): (energy, nodal forces (n, 3), dense Hessian "
          "(3n, 3n)), for checking against finite differences (small bodies only).")
      .def(
          "contact_potential",
          [](const Simulation& s, const PointsIn& positions) {
            const Simulation::Claim claim(s, "evaluating the contact potential");
            const Nodes y = nodes_from(positions, "positions");
            if (y.cols() != s.num_nodes()) throw InvalidInput("positions must have one row per node");
            const auto& cs = s.contacts().contacts();
            double energy = 0;
            Eigen::MatrixXd forces(cs.size(), 3), hessians(3 * cs.size(), 3);
            for (size_t k = 0; k < cs.size(); ++k) {
              Mat3 h;
              const Vec3 yk = s.contacts().relative(cs[k], y);
              energy += s.contacts().energy_of(cs[k], yk);
              forces.row(k) = s.contacts().force_of(cs[k], yk, &h);
              hessians.block(3 * k, 0, 3, 3) = h;
            }
            return py::make_tuple(energy, forces, hessians);
          },
          py::arg("positions"),
          "The last step's contact potentials at positions (n, 3): (energy, force per contact (m, 3), Hessian "
          "per contact (3m, 3)), for checking them against finite differences.");
}
