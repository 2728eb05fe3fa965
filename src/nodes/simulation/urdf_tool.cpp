#include "urdf_tool.h"

#include <urdf_parser/urdf_parser.h>

#include <stdexcept>

namespace tt_nodes {

std::vector<tt::ToolShape> toolShapesFromUrdf(const std::string& xml,
                                              std::vector<std::string>* skipped) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
  if (!model) throw std::runtime_error("/robot_description: not a valid URDF");
  std::vector<tt::ToolShape> shapes;
  for (const auto& [name, link] : model->links_) {
    for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
      if (!collision || !collision->geometry) continue;
      tt::ToolShape s;
      s.link = name;
      s.jaw = name.find("jaw") != std::string::npos;
      const urdf::Pose& o = collision->origin;
      double qx, qy, qz, qw;
      o.rotation.getQuaternion(qx, qy, qz, qw);
      s.offset.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
      s.offset.translation() = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
      const urdf::Geometry& g = *collision->geometry;
      if (g.type == urdf::Geometry::SPHERE) {
        s.type = tt::ToolShape::Type::kSphere;
        s.radius = static_cast<const urdf::Sphere&>(g).radius;
      } else if (g.type == urdf::Geometry::BOX) {
        const urdf::Vector3& d = static_cast<const urdf::Box&>(g).dim;
        s.type = tt::ToolShape::Type::kBox;
        s.size = Eigen::Vector3d(d.x, d.y, d.z);
      } else if (g.type == urdf::Geometry::CYLINDER) {
        const auto& c = static_cast<const urdf::Cylinder&>(g);
        s.type = tt::ToolShape::Type::kCylinder;
        s.radius = c.radius;
        s.length = c.length;
      } else {
        if (skipped) skipped->push_back("link '" + name + "': mesh collision geometry not used");
        continue;
      }
      shapes.push_back(s);
    }
  }
  return shapes;
}

}  // namespace tt_nodes
