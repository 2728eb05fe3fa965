#include "offscreen_renderer.h"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <cmath>
#include <stdexcept>

namespace tt_render {

namespace {

constexpr int kSegments = 24;  // around cylinders and spheres

void color(const Rgb& c) { glColor3f(c.r, c.g, c.b); }

}  // namespace

struct OffscreenRenderer::Context {
  OSMesaContext gl = nullptr;
  std::vector<std::uint8_t> buffer;  // RGBA, bottom row first
};

std::vector<float> vertexNormals(const std::vector<float>& positions,
                                 const std::vector<std::uint32_t>& triangles) {
  const std::size_t nv = positions.size() / 3;
  std::vector<Eigen::Vector3d> sum(nv, Eigen::Vector3d::Zero());
  const auto p = [&](std::uint32_t i) {
    return Eigen::Vector3d(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
  };
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    if (a >= nv || b >= nv || c >= nv) continue;
    const Eigen::Vector3d n = (p(b) - p(a)).cross(p(c) - p(a));  // |n| = 2 area
    sum[a] += n;
    sum[b] += n;
    sum[c] += n;
  }
  std::vector<float> normals(3 * nv, 0.0f);
  for (std::size_t i = 0; i < nv; ++i) {
    const double len = sum[i].norm();
    if (len > 0.0 && std::isfinite(len))
      for (int k = 0; k < 3; ++k) normals[3 * i + k] = static_cast<float>(sum[i][k] / len);
  }
  return normals;
}

OffscreenRenderer::OffscreenRenderer(int width, int height)
    : context_(new Context), width_(width), height_(height) {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
    throw std::runtime_error("OffscreenRenderer: image size out of range");
  context_->gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!context_->gl) throw std::runtime_error("OffscreenRenderer: OSMesaCreateContextExt failed");
  context_->buffer.assign(std::size_t(width) * height * 4, 0);
  makeCurrent();
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_NORMALIZE);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  glShadeModel(GL_SMOOTH);
  const GLfloat ambient[] = {0.15f, 0.15f, 0.15f, 1.0f}, diffuse[] = {0.9f, 0.9f, 0.9f, 1.0f};
  const GLfloat specular[] = {0.3f, 0.3f, 0.3f, 1.0f};
  glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT0, GL_SPECULAR, specular);
  const GLfloat shininess = 24.0f, materialSpecular[] = {0.25f, 0.25f, 0.25f, 1.0f};
  glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, materialSpecular);
  glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, shininess);
  setCamera(camera_);
}

OffscreenRenderer::~OffscreenRenderer() {
  if (context_->gl) OSMesaDestroyContext(context_->gl);
}

std::string OffscreenRenderer::glRenderer() const {
  const GLubyte* s = glGetString(GL_RENDERER);
  return s ? reinterpret_cast<const char*>(s) : "unknown";
}

void OffscreenRenderer::makeCurrent() {
  if (!OSMesaMakeCurrent(context_->gl, context_->buffer.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw std::runtime_error("OffscreenRenderer: OSMesaMakeCurrent failed");
}

Eigen::Matrix4d OffscreenRenderer::viewMatrix() const {
  const Eigen::Vector3d f = (camera_.target - camera_.position).normalized();
  const Eigen::Vector3d s = f.cross(camera_.up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d v = Eigen::Matrix4d::Identity();
  v.block<1, 3>(0, 0) = s.transpose();
  v.block<1, 3>(1, 0) = u.transpose();
  v.block<1, 3>(2, 0) = -f.transpose();
  v(0, 3) = -s.dot(camera_.position);
  v(1, 3) = -u.dot(camera_.position);
  v(2, 3) = f.dot(camera_.position);
  return v;
}

Eigen::Matrix4d OffscreenRenderer::projectionMatrix() const {
  const double t = 1.0 / std::tan(0.5 * camera_.fovDeg * M_PI / 180.0);
  const double aspect = double(width_) / double(height_);
  const double n = camera_.nearPlane, f = camera_.farPlane;
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = (f + n) / (n - f);
  p(2, 3) = 2.0 * f * n / (n - f);
  p(3, 2) = -1.0;
  return p;
}

void OffscreenRenderer::setCamera(const Camera& camera) {
  const Eigen::Vector3d f = camera.target - camera.position;
  if (!(f.norm() > 0.0) || !(f.normalized().cross(camera.up).norm() > 1e-6) ||
      !(camera.fovDeg > 0.0 && camera.fovDeg < 180.0) ||
      !(camera.nearPlane > 0.0 && camera.farPlane > camera.nearPlane))
    throw std::runtime_error(
        "OffscreenRenderer: camera needs target != position, up not along the view, "
        "0 < fov < 180 and 0 < near < far");
  camera_ = camera;
}

void OffscreenRenderer::beginFrame() {
  makeCurrent();
  glViewport(0, 0, width_, height_);
  glClearColor(background_.r, background_.g, background_.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  const Eigen::Matrix4d p = projectionMatrix();
  glLoadMatrixd(p.data());  // Eigen is column-major, as GL
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  const GLfloat headlight[] = {0.0f, 0.0f, 0.0f, 1.0f};  // at the eye, in eye coordinates
  glLightfv(GL_LIGHT0, GL_POSITION, headlight);
}

void OffscreenRenderer::loadModel(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix4d m = viewMatrix() * pose.matrix();
  glLoadMatrixd(m.data());
}

void OffscreenRenderer::drawMesh(const std::vector<float>& positions, const std::vector<float>& normals,
                                 const std::vector<std::uint32_t>& triangles, const Rgb& c) {
  if (normals.size() != positions.size())
    throw std::invalid_argument("OffscreenRenderer::drawMesh: one normal per vertex expected");
  const std::size_t nv = positions.size() / 3;
  for (std::uint32_t i : triangles)
    if (i >= nv) throw std::invalid_argument("OffscreenRenderer::drawMesh: triangle index out of range");
  loadModel(Eigen::Isometry3d::Identity());
  color(c);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, positions.data());
  glNormalPointer(GL_FLOAT, 0, normals.data());
  glDrawElements(GL_TRIANGLES, GLsizei(triangles.size() / 3 * 3), GL_UNSIGNED_INT, triangles.data());
  glDisableClientState(GL_NORMAL_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
}

void OffscreenRenderer::drawCylinder(const Eigen::Isometry3d& pose, double radius, double length,
                                     const Rgb& c) {
  loadModel(pose);
  color(c);
  const double h = 0.5 * length;
  glBegin(GL_QUAD_STRIP);
  for (int i = 0; i <= kSegments; ++i) {
    const double a = 2.0 * M_PI * i / kSegments, x = std::cos(a), y = std::sin(a);
    glNormal3d(x, y, 0.0);
    glVertex3d(radius * x, radius * y, h);
    glVertex3d(radius * x, radius * y, -h);
  }
  glEnd();
  for (int side = -1; side <= 1; side += 2) {  // end caps
    glBegin(GL_TRIANGLE_FAN);
    glNormal3d(0.0, 0.0, side);
    glVertex3d(0.0, 0.0, side * h);
    for (int i = 0; i <= kSegments; ++i) {
      const double a = side * 2.0 * M_PI * i / kSegments;
      glVertex3d(radius * std::cos(a), radius * std::sin(a), side * h);
    }
    glEnd();
  }
}

void OffscreenRenderer::drawBox(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, const Rgb& c) {
  loadModel(pose);
  color(c);
  const Eigen::Vector3d h = 0.5 * size;
  glBegin(GL_QUADS);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = -1; side <= 1; side += 2) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = side;
      glNormal3d(n.x(), n.y(), n.z());
      const double us[] = {-1, 1, 1, -1}, vs[] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector3d p;
        p[axis] = side * h[axis];
        p[u] = us[k] * h[u];
        p[v] = side * vs[k] * h[v];  // counter-clockwise seen from outside
        glVertex3d(p.x(), p.y(), p.z());
      }
    }
  }
  glEnd();
}

void OffscreenRenderer::drawSphere(const Eigen::Isometry3d& pose, double radius, const Rgb& c) {
  loadModel(pose);
  color(c);
  const int rings = kSegments / 2;
  for (int i = 0; i < rings; ++i) {
    const double t0 = M_PI * i / rings, t1 = M_PI * (i + 1) / rings;
    glBegin(GL_QUAD_STRIP);
    for (int j = 0; j <= kSegments; ++j) {
      const double p = 2.0 * M_PI * j / kSegments;
      for (double t : {t0, t1}) {
        const Eigen::Vector3d n(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
        glNormal3d(n.x(), n.y(), n.z());
        glVertex3d(radius * n.x(), radius * n.y(), radius * n.z());
      }
    }
    glEnd();
  }
}

void OffscreenRenderer::readRgb(std::vector<std::uint8_t>& rgb) {
  glFinish();
  rgb.resize(std::size_t(width_) * height_ * 3);
  const std::vector<std::uint8_t>& src = context_->buffer;
  for (int row = 0; row < height_; ++row) {
    const std::uint8_t* in = &src[std::size_t(height_ - 1 - row) * width_ * 4];
    std::uint8_t* out = &rgb[std::size_t(row) * width_ * 3];
    for (int col = 0; col < width_; ++col) {
      out[3 * col] = in[4 * col];
      out[3 * col + 1] = in[4 * col + 1];
      out[3 * col + 2] = in[4 * col + 2];
    }
  }
}

bool OffscreenRenderer::project(const Eigen::Vector3d& world, double& column, double& row) const {
  const Eigen::Vector4d clip = projectionMatrix() * viewMatrix() * world.homogeneous();
  if (!(clip.w() > 0.0)) return false;
  const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
  column = 0.5 * (x + 1.0) * width_;
  row = 0.5 * (1.0 - y) * height_;
  return true;
}

}  // namespace tt_render
