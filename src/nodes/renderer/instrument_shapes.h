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
  // Default instrument only: +1 / -1 for the upper / lower jaw, turned open by half the jaw
  // angle each about the tip frame's x (as the URDF's mimic joints turn jaw_upper and
  // jaw_lower); 0 for the rest.
  int jawSide = 0;
};

// Where a shape's link frame is for the default instrument at tipPose with the jaws opened
// by jawAngle (rad).
Eigen::Isometry3d defaultInstrumentLinkPose(const Shape& shape, const Eigen::Isometry3d& tipPose,
                                            double jawAngle);

// Shapes of every link of the URDF text that has visual or collision geometry (meshes are
// skipped). Throws std::runtime_error when the URDF does not parse.
std::vector<Shape> shapesFromUrdf(const std::string& urdfXml);

// A default laparoscopic grasper in the `tipFrame`: shaft of `shaftLength` behind the tip, a
// collar at its end, two 18 mm jaws hinged at the tip (pose them with
// defaultInstrumentLinkPose).
std::vector<Shape> defaultInstrument(const std::string& tipFrame, double shaftLength);

// Draws the shapes, each at linkPose(shape.link) * shape.origin.
void drawShapes(OffscreenRenderer& r, const std::vector<Shape>& shapes,
                const std::vector<Eigen::Isometry3d>& linkPoses);

}  // namespace tt_render
