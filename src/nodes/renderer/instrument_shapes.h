#pragma once
// The instrument as simple shapes in the frames of its links: from a URDF (visual geometry,
// else collision geometry, via urdfdom) or, without one, a default shaft and jaws in the
// instrument_tip frame (shaft along -z behind the tip, as the tip frame's +z points from the
// trocar toward the tip).
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "offscreen_renderer.h"

namespace tt_render {

struct Shape {
  enum Type { kCylinder, kBox, kSphere } type = kCylinder;
  std::string link;                                  // frame the shape is attached to
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // in the link frame
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // cylinder: radius, length; box: x y z; sphere: r
  Rgb color{0.75f, 0.78f, 0.82f};
};

// Shapes of every link of the URDF text that has visual or collision geometry (meshes are
// skipped). Throws std::runtime_error when the URDF does not parse.
std::vector<Shape> shapesFromUrdf(const std::string& urdfXml);

// A default laparoscopic grasper in the `tipFrame`: shaft of `shaftLength` behind the tip.
std::vector<Shape> defaultInstrument(const std::string& tipFrame, double shaftLength);

// Draws the shapes, each at linkPose(shape.link) * shape.origin.
void drawShapes(OffscreenRenderer& r, const std::vector<Shape>& shapes,
                const std::vector<Eigen::Isometry3d>& linkPoses);

}  // namespace tt_render
