// Separate parts riding along a morphing body (morph/ride_along.h) and the
// split of a mesh into its connected parts that finds them (TriMesh).

#include <cmath>
#include <memory>
#include <vector>

#include "mesh/tri_mesh.h"
#include "morph/ride_along.h"
#include "python/arrays.h"
#include "python/bindings.h"

namespace paramorph::python {

void bind_ride_along(py::module_& m) {
  m.def(
      "vertex_parts",
      [](const py::object& F, Index vertices) {
        // A count no mesh in memory has (an int's top) would only be an allocation failure.
        constexpr Index kMostVertices = Index(1) << 25;
        PM_REQUIRE(vertices >= 0 && vertices <= kMostVertices, InvalidInputError, "vertices must be in [0, ",
                   kMostVertices, "], got ", vertices);
        const MatrixX3i f = to_faces(F, "F");
        PM_REQUIRE(f.size() == 0 || (f.minCoeff() >= 0 && f.maxCoeff() < vertices), InvalidInputError,
                   "F has an index outside [0, ", vertices, ")");
        const TriMesh mesh(MatrixX3d::Zero(vertices, 3), f);
        return to_numpy(mesh.vertex_component());
      },
      py::arg("F"), py::arg("vertices"),
      "(vertices,) int32: the connected part of each vertex, numbered 0.. in the order of their lowest "
      "vertex; a vertex in no face is a part of its own.");

  py::class_<morph::PartRider>(m, "PartRider", R"doc(Separate parts (eyes, teeth, buttons) carried by a
morphing body: each keeps its shape and moves with the similarity (rotation,
uniform scale, translation) that best takes the patch of body around where it
sits from rest to the body's shape now, and is pushed out along the patch's
normal where it would sit deeper in the body than at rest.

body_V, body_F: the body at rest, closed and facing outward. part_V: (p, 3)
every part vertex at rest; part_of: (p,) which part each is in, labels 0..k-1
each used. patch_scale: how far the patch reaches, in part sizes; min_patch:
the fewest body vertices in it. A part farther from the body than its own
size and attach_share of the body's diagonal does not ride (`riding`) and
stays where it was. InvalidInputError for malformed input.)doc")
      .def(py::init([](const py::object& body_V, const py::object& body_F, const py::object& part_V,
                       const py::object& part_of, double patch_scale, Index min_patch, double attach_share) {
             const MatrixX3d bv = to_vertices(body_V, "body_V"), pv = to_vertices(part_V, "part_V");
             const MatrixX3i bf = to_faces(body_F, "body_F");
             const std::vector<Index> labels = to_indices(part_of, "part_of");
             PM_REQUIRE(patch_scale > 0 && std::isfinite(patch_scale), InvalidInputError,
                        "patch_scale must be > 0, got ", patch_scale);
             PM_REQUIRE(min_patch >= 1, InvalidInputError, "min_patch must be >= 1, got ", min_patch);
             VectorXi of(Index(labels.size()));
             for (std::size_t k = 0; k < labels.size(); ++k) of(Index(k)) = labels[k];
             morph::RideAlongOptions options;
             options.patch_scale = patch_scale;
             options.min_patch = min_patch;
             PM_REQUIRE(attach_share >= 0 && std::isfinite(attach_share), InvalidInputError,
                        "attach_share must be >= 0, got ", attach_share);
             options.attach_share = attach_share;
             py::gil_scoped_release release;
             return std::make_unique<morph::PartRider>(bv, bf, pv, of, options);
           }),
           py::arg("body_V"), py::arg("body_F"), py::arg("part_V"), py::arg("part_of"), py::kw_only(),
           py::arg("patch_scale") = 1.5, py::arg("min_patch") = 12, py::arg("attach_share") = 0.1)
      .def(
          "at",
          [](const morph::PartRider& self, const py::object& body_now) {
            const MatrixX3d now = to_vertices(body_now, "body_now");
            morph::CarriedParts carried;
            {
              py::gil_scoped_release release;
              carried = self.at(now);
            }
            return py::make_tuple(to_numpy(carried.positions), to_numpy(carried.pushed));
          },
          py::arg("body_now"),
          "(positions (p, 3), pushed (k,)): the part vertices carried by the body at body_now (its rest "
          "faces), and how far each part was pushed out so as to sit no deeper than at rest.")
      .def_property_readonly("parts", &morph::PartRider::parts)
      .def_property_readonly("patch_sizes", [](const morph::PartRider& self) {
        std::vector<Index> sizes;
        for (const auto& patch : self.patches()) sizes.push_back(Index(patch.size()));
        return to_numpy(sizes);
      }, "(k,) body vertices in each part's patch")
      .def_property_readonly("riding", [](const morph::PartRider& self) {
        py::array_t<bool> out(py::ssize_t(self.parts()));
        auto w = out.mutable_unchecked<1>();
        for (Index p = 0; p < self.parts(); ++p) w(p) = self.riding()[p];
        return out;
      }, "(k,) bool: the part rides along (else it stays where it was: farther from the body than its "
         "own size and attach_share of the body's diagonal)")
      .def_property_readonly("rest_gap", [](const morph::PartRider& self) { return to_numpy(self.rest_gap()); },
                             "(k,) each part's gap to the body at rest (0: touching or inside)")
      .def_property_readonly("rest_depth", [](const morph::PartRider& self) { return to_numpy(self.rest_depth()); },
                             "(k,) how deep each part sat inside the body at rest (0: outside)");

  m.def(
      "signed_distance",
      [](const py::object& V, const py::object& F, const py::object& points) {
        const MatrixX3d v = to_vertices(V, "V"), q = to_vertices(points, "points");
        const MatrixX3i f = to_faces(F, "F");
        VectorXd out;
        {
          py::gil_scoped_release release;
          out = morph::signed_distance(v, f, q);
        }
        return to_numpy(out);
      },
      py::arg("V"), py::arg("F"), py::arg("points"),
      "(q,) signed distance of each point to the closed, outward mesh (V, F): negative inside.");
}

}  // namespace paramorph::python
