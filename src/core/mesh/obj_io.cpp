// Wavefront OBJ surfaces: v and f lines (f a, a/b, a/b/c, a//c; negative indices count back
// from the last vertex read); polygons are fanned into triangles. Other lines are ignored.
#include <fstream>

#include "text_scanner.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "write_support.h"

namespace tt {

namespace {

int objVertexIndex(const meshio::Scanner& s, std::string_view ref, long long vertexCount) {
  const std::string_view number = ref.substr(0, ref.find('/'));
  const long long v = s.toInt(number, "vertex index in face reference " + meshio::quoted(ref));
  const long long index = v < 0 ? vertexCount + v : v - 1;
  if (v == 0 || index < 0 || index >= vertexCount)
    s.fail("expected a vertex index in [1, " + std::to_string(vertexCount) + "] or [-" +
           std::to_string(vertexCount) + ", -1], got " + std::to_string(v));
  return static_cast<int>(index);
}

}  // namespace

SurfaceMesh readObj(const std::string& path) {
  const std::string text = meshio::loadTextFile(path);
  meshio::Scanner s(path, text, '#');
  std::vector<double> xyz;
  std::vector<Triangle> triangles;
  std::vector<int> polygon;
  while (s.nextLine()) {
    if (s[0] == "v") {
      if (s.size() < 4 || s.size() > 7) s.fail("expected 'v x y z' with 3 coordinates (optionally w or a colour), got " + std::to_string(s.size() - 1) + " values");
      const std::string what = "3 coordinates of vertex " + std::to_string(xyz.size() / 3 + 1);
      for (int k = 1; k <= 3; ++k) xyz.push_back(s.toDouble(s[k], what));
      for (std::size_t k = 4; k < s.size(); ++k) s.toDouble(s[k], "vertex weight or colour");
    } else if (s[0] == "f") {
      if (s.size() < 4) s.fail("expected a face with at least 3 vertices, got " + std::to_string(s.size() - 1));
      const long long count = static_cast<long long>(xyz.size() / 3);
      polygon.clear();
      for (std::size_t k = 1; k < s.size(); ++k) {
        const int v = objVertexIndex(s, s[k], count);
        for (int other : polygon)
          if (other == v) s.fail("expected distinct vertices in a face, vertex " + std::to_string(v + 1) + " is repeated");
        polygon.push_back(v);
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
  }
  if (triangles.empty()) throw InputError(path, s.lineNo(), "expected at least one face ('f' line), found none");
  SurfaceMesh surface;
  surface.vertices = Eigen::Map<const Eigen::Matrix3Xd>(xyz.data(), 3, static_cast<Eigen::Index>(xyz.size() / 3));
  surface.triangles = std::move(triangles);
  return surface;
}

void writeObj(const std::string& path, const SurfaceMesh& surface) {
  meshio::TextWriter out(path);
  for (Eigen::Index i = 0; i < surface.vertices.cols(); ++i) {
    out << "v";
    for (int k = 0; k < 3; ++k) out << " " << meshio::number(surface.vertices(k, i));
    out << "\n";
  }
  for (const Triangle& t : surface.triangles)
    out << "f " << (t[0] + 1) << " " << (t[1] + 1) << " " << (t[2] + 1) << "\n";
  out.close();
}

}  // namespace tt
