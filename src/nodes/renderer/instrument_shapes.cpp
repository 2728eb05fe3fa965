#include "instrument_shapes.h"

#include <stdexcept>

#include <urdf_parser/urdf_parser.h>

namespace tt_render {

namespace {

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized().toRotationMatrix();
  return t;
}

// False for geometry that is not drawn (meshes, none).
bool toShape(const urdf::GeometrySharedPtr& g, Shape& s) {
  if (!g) return false;
  switch (g->type) {
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(*g);
      s.type = Shape::kCylinder;
      s.size = Eigen::Vector3d(c.radius, c.length, 0.0);
      return true;
    }
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(*g);
      s.type = Shape::kBox;
      s.size = Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
      return true;
    }
    case urdf::Geometry::SPHERE: {
      s.type = Shape::kSphere;
      s.size = Eigen::Vector3d(static_cast<const urdf::Sphere&>(*g).radius, 0.0, 0.0);
      return true;
    }
    default:
      return false;
  }
}

}  // namespace

std::vector<Shape> shapesFromUrdf(const std::string& urdfXml) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdfXml);
  if (!model) throw std::runtime_error("the URDF does not parse");
  std::vector<Shape> shapes;
  for (const auto& entry : model->links_) {
    const urdf::LinkSharedPtr& link = entry.second;
    bool drawn = false;
    for (const auto& v : link->visual_array) {
      Shape s;
      s.link = link->name;
      if (!v || !toShape(v->geometry, s)) continue;
      s.origin = toIsometry(v->origin);
      if (v->material && v->material->color.a > 0.0f)
        s.color = Rgb{v->material->color.r, v->material->color.g, v->material->color.b};
      shapes.push_back(s);
      drawn = true;
    }
    if (drawn) continue;
    for (const auto& c : link->collision_array) {
      Shape s;
      s.link = link->name;
      if (!c || !toShape(c->geometry, s)) continue;
      s.origin = toIsometry(c->origin);
      shapes.push_back(s);
    }
  }
  return shapes;
}

std::vector<Shape> defaultInstrument(const std::string& tipFrame, double shaftLength) {
  std::vector<Shape> shapes(3);
  shapes[0].link = tipFrame;  // shaft, 5 mm, ending at the jaw pivot
  shapes[0].size = Eigen::Vector3d(0.0025, shaftLength, 0.0);
  shapes[0].origin.translation() = Eigen::Vector3d(0.0, 0.0, -0.5 * shaftLength);
  for (int j = 1; j <= 2; ++j) {  // two jaws ahead of the pivot
    shapes[j].link = tipFrame;
    shapes[j].type = Shape::kBox;
    shapes[j].size = Eigen::Vector3d(0.0018, 0.0012, 0.012);
    shapes[j].origin.translation() = Eigen::Vector3d(0.0, j == 1 ? 0.001 : -0.001, 0.006);
    shapes[j].color = Rgb{0.35f, 0.36f, 0.40f};
  }
  return shapes;
}

void drawShapes(OffscreenRenderer& r, const std::vector<Shape>& shapes,
                const std::vector<Eigen::Isometry3d>& linkPoses) {
  for (std::size_t i = 0; i < shapes.size() && i < linkPoses.size(); ++i) {
    const Shape& s = shapes[i];
    const Eigen::Isometry3d pose = linkPoses[i] * s.origin;
    switch (s.type) {
      case Shape::kCylinder: r.drawCylinder(pose, s.size.x(), s.size.y(), s.color); break;
      case Shape::kBox: r.drawBox(pose, s.size, s.color); break;
      case Shape::kSphere: r.drawSphere(pose, s.size.x(), s.color); break;
    }
  }
}

}  // namespace tt_render
