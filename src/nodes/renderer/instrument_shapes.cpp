#include "instrument_shapes.h"

#include <cmath>
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
  const Rgb steelGrey{0.72f, 0.74f, 0.78f}, jawGrey{0.30f, 0.31f, 0.34f};
  std::vector<Shape> shapes(4);
  shapes[0].link = tipFrame;  // shaft, 5 mm, ending 3 mm behind the jaw pivot
  shapes[0].size = Eigen::Vector3d(0.0025, shaftLength, 0.0);
  shapes[0].origin.translation() = Eigen::Vector3d(0.0, 0.0, -0.003 - 0.5 * shaftLength);
  shapes[0].color = steelGrey;
  shapes[1].link = tipFrame;  // the clevis holding the jaw pivot
  shapes[1].size = Eigen::Vector3d(0.0022, 0.006, 0.0);
  shapes[1].origin.translation() = Eigen::Vector3d(0.0, 0.0, -0.003);
  shapes[1].color = Rgb{0.55f, 0.56f, 0.60f};
  for (int j = 2; j <= 3; ++j) {  // two jaws ahead of the pivot, as the URDF's
    Shape& jaw = shapes[j];
    jaw.link = tipFrame;
    jaw.type = Shape::kBox;
    jaw.jawSide = j == 2 ? 1 : -1;
    jaw.size = Eigen::Vector3d(0.004, 0.0016, 0.018);
    jaw.origin.translation() = Eigen::Vector3d(0.0, jaw.jawSide * 0.0008, 0.009);
    jaw.color = jawGrey;
  }
  return shapes;
}

Eigen::Isometry3d defaultInstrumentLinkPose(const Shape& shape, const Eigen::Isometry3d& tipPose,
                                            double jawAngle) {
  if (shape.jawSide == 0 || !std::isfinite(jawAngle)) return tipPose;
  Eigen::Isometry3d hinge = Eigen::Isometry3d::Identity();
  hinge.linear() = Eigen::AngleAxisd(0.5 * jawAngle * shape.jawSide, -Eigen::Vector3d::UnitX()).toRotationMatrix();
  return tipPose * hinge;
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
