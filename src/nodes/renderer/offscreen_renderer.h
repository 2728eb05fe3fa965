#pragma once
// Offscreen OpenGL rendering with OSMesa (no display, no X): a camera, a lit triangle mesh,
// the instrument as cylinders, boxes and spheres, the abdominal cavity around them, and the
// RGB image read back. The laparoscope's look comes from one per-pixel shader (GLSL 1.20):
// the light sits at the scope tip and falls off with distance, surfaces have a Blinn-Phong
// highlight (sharp and strong on wet tissue), a procedural noise texture and a vignette
// darkens the image corners. Without GLSL it falls back to fixed-function GL with a
// headlight. No ROS here, so it can be unit-tested on its own.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace tt_render {

struct Rgb {
  float r, g, b;
};

// How a surface takes the light (per draw call; see setMaterial).
struct Material {
  float specular = 0.25f;   // strength of the white highlight (0..1)
  float shininess = 24.0f;  // Blinn-Phong exponent: larger = smaller, sharper highlight
  float texture = 0.0f;     // relative amplitude of the procedural texture (0: none)
  float textureScale = 400.0f;  // 1/m: the texture's finest cells are about 1/scale wide
  bool perVertex = false;   // light per vertex, no texture: cheaper for large smooth surfaces
};

// Wet liver parenchyma: a strong, sharp highlight and a fine mottled texture.
Material wetTissue();
// Peritoneum lining the cavity: weaker highlight, lit per vertex (it fills much of the image).
Material cavityWall();
// Stainless steel instrument.
Material steel();

// The scope's light and lens.
struct Lighting {
  double intensity = 1.6;  // diffuse light at the scope tip (1: the surface colour itself)
  double range = 0.18;     // m: the light is at half strength this far from the scope tip
  double ambient = 0.08;   // light everywhere, as a fraction of the light at the tip
  double vignette = 0.55;  // darkening of the image corners (0: none, 1: black)
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
  void setLighting(const Lighting& l) { lighting_ = l; }
  const Lighting& lighting() const { return lighting_; }
  // For the draws that follow (beginFrame resets it to the default Material).
  void setMaterial(const Material& m) { material_ = m; }
  // False when the GL has no GLSL: fixed-function headlight, no fall-off, texture or vignette.
  bool shaded() const { return program_ != 0; }

  // Clears the frame; then draw, then readRgb.
  void beginFrame();
  // Triangles with per-vertex normals (normals.size() == positions.size()).
  void drawMesh(const std::vector<float>& positions, const std::vector<float>& normals,
                const std::vector<std::uint32_t>& triangles, const Rgb& color);
  // Shapes in the world at `pose` (URDF conventions: centred, cylinder axis along local z).
  void drawCylinder(const Eigen::Isometry3d& pose, double radius, double length, const Rgb& color);
  void drawBox(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, const Rgb& color);
  void drawSphere(const Eigen::Isometry3d& pose, double radius, const Rgb& color);
  // The inside of an ellipsoid (centre, semi-axes along world x y z): the cavity around the
  // organ, lit from within.
  void drawCavity(const Eigen::Vector3d& centre, const Eigen::Vector3d& radii, const Rgb& color);

  // The frame as RGB bytes, top row first (width * height * 3).
  void readRgb(std::vector<std::uint8_t>& rgb);

  // Where a world point lands in the image (column, row from the top); false behind the camera.
  bool project(const Eigen::Vector3d& world, double& column, double& row) const;

 private:
  void makeCurrent();
  void loadModel(const Eigen::Isometry3d& pose);
  void buildProgram();
  void applyMaterial(const Eigen::Isometry3d& model);
  void sphereStrip(const Eigen::Vector3d& radii, bool inward);
  Eigen::Matrix4d viewMatrix() const;
  Eigen::Matrix4d projectionMatrix() const;

  struct Context;
  std::unique_ptr<Context> context_;
  int width_, height_;
  Camera camera_;
  Rgb background_{0.08f, 0.05f, 0.05f};
  Lighting lighting_;
  Material material_;
  unsigned program_ = 0;        // per-pixel GL program, 0 without GLSL
  unsigned vertexProgram_ = 0;  // per-vertex GL program (Material::perVertex)
};

}  // namespace tt_render
