#pragma once
// Offscreen OpenGL rendering with OSMesa (no display, no X): a camera, a lit triangle mesh,
// the instrument as cylinders, boxes and spheres, and the RGB image read back. Legacy
// fixed-function GL with a headlight. No ROS here, so it can be unit-tested on its own.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace tt_render {

struct Rgb {
  float r, g, b;
};

struct Camera {
  Eigen::Vector3d position{0.01, 0.12, 0.21};  // beside the trocar (-0.035, 0.075, 0.20)
  Eigen::Vector3d target{-0.036, 0.067, 0.013};  // centre of the liver
  Eigen::Vector3d up{0.0, 1.0, 0.0};
  double fovDeg = 50.0;  // vertical field of view
  double nearPlane = 0.005, farPlane = 2.0;  // m
};

// Per-vertex normals of a triangle mesh: area-weighted sums of the face normals (right-hand
// orientation), normalised. positions: x y z per vertex; triangles: three indices each.
std::vector<float> vertexNormals(const std::vector<float>& positions,
                                 const std::vector<std::uint32_t>& triangles);

class OffscreenRenderer {
 public:
  // Throws std::runtime_error when no OSMesa context can be made.
  OffscreenRenderer(int width, int height);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  int width() const { return width_; }
  std::string glRenderer() const;  // GL_RENDERER, e.g. llvmpipe
  int height() const { return height_; }

  void setCamera(const Camera& camera);
  const Camera& camera() const { return camera_; }
  void setBackground(const Rgb& c) { background_ = c; }

  // Clears the frame; then draw, then readRgb.
  void beginFrame();
  // Triangles with per-vertex normals (normals.size() == positions.size()).
  void drawMesh(const std::vector<float>& positions, const std::vector<float>& normals,
                const std::vector<std::uint32_t>& triangles, const Rgb& color);
  // Shapes in the world at `pose` (URDF conventions: centred, cylinder axis along local z).
  void drawCylinder(const Eigen::Isometry3d& pose, double radius, double length, const Rgb& color);
  void drawBox(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, const Rgb& color);
  void drawSphere(const Eigen::Isometry3d& pose, double radius, const Rgb& color);

  // The frame as RGB bytes, top row first (width * height * 3).
  void readRgb(std::vector<std::uint8_t>& rgb);

  // Where a world point lands in the image (column, row from the top); false behind the camera.
  bool project(const Eigen::Vector3d& world, double& column, double& row) const;

 private:
  void makeCurrent();
  void loadModel(const Eigen::Isometry3d& pose);
  Eigen::Matrix4d viewMatrix() const;
  Eigen::Matrix4d projectionMatrix() const;

  struct Context;
  std::unique_ptr<Context> context_;
  int width_, height_;
  Camera camera_;
  Rgb background_{0.08f, 0.05f, 0.05f};
};

}  // namespace tt_render
