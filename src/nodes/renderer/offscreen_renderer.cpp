#include "offscreen_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tt_render {

namespace {

constexpr int kSegments = 24;        // around cylinders and spheres
constexpr int kCavitySegments = 48;  // around the cavity (large on screen)

void color(const Rgb& c) { glColor3f(c.r, c.g, c.b); }

// Per-pixel lighting in eye coordinates. The light is at the scope tip (the eye); its
// diffuse part falls off as 1 / (1 + (d / range)^2) (an inverse square law that stays finite
// at the tip); the highlight is Blinn-Phong. The texture multiplies the surface colour by
// 1 + amplitude (n - 1/2), n two octaves of value noise on the world position (so it sticks
// to the tissue as it deforms only as far as the vertices move; enough for a mottled look).
const char* kVertexShader = R"(#version 120
uniform mat4 uModel;
varying vec3 vEye;
varying vec3 vNormal;
varying vec3 vWorld;
void main() {
  vec4 eye = gl_ModelViewMatrix * gl_Vertex;
  vEye = eye.xyz;
  vNormal = gl_NormalMatrix * gl_Normal;
  vWorld = (uModel * gl_Vertex).xyz;
  gl_FrontColor = gl_Color;
  gl_Position = gl_ProjectionMatrix * eye;
}
)";

const char* kFragmentShader = R"(#version 120
uniform float uIntensity, uRange, uAmbient, uVignette;
uniform float uSpecular, uShininess, uTexture, uTextureScale;
uniform vec2 uViewport;
varying vec3 vEye;
varying vec3 vNormal;
varying vec3 vWorld;
float cellValue(vec3 cell) {  // a pseudo-random value in [0, 1) per lattice cell, no sin()
  vec3 q = fract(cell * vec3(0.1371, 0.2113, 0.1789) + vec3(0.31, 0.57, 0.73));
  q += dot(q, q.zxy + 19.19);
  return fract(q.x * q.y + q.z);
}
float valueNoise(vec3 p) {
  vec3 cell = floor(p);
  vec3 f = fract(p);
  f = f * f * (3.0 - 2.0 * f);
  float x00 = mix(cellValue(cell), cellValue(cell + vec3(1, 0, 0)), f.x);
  float x10 = mix(cellValue(cell + vec3(0, 1, 0)), cellValue(cell + vec3(1, 1, 0)), f.x);
  float x01 = mix(cellValue(cell + vec3(0, 0, 1)), cellValue(cell + vec3(1, 0, 1)), f.x);
  float x11 = mix(cellValue(cell + vec3(0, 1, 1)), cellValue(cell + vec3(1, 1, 1)), f.x);
  return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
}
void main() {
  vec3 toLight = -vEye;  // the light is at the scope tip, the eye
  float d = length(toLight);
  vec3 l = toLight / max(d, 1e-6);
  vec3 n = normalize(vNormal);
  if (dot(n, l) < 0.0) n = -n;  // two-sided: the side the scope sees
  float falloff = 1.0 / (1.0 + (d / uRange) * (d / uRange));
  float diffuse = max(dot(n, l), 0.0);
  float highlight = pow(max(dot(n, l), 0.0), uShininess);  // half vector = l: light at the eye
  vec3 base = gl_Color.rgb;
  if (uTexture > 0.0) {
    float t = 0.65 * valueNoise(vWorld * uTextureScale) + 0.35 * valueNoise(vWorld * (3.1 * uTextureScale));
    base *= 1.0 + uTexture * (t - 0.5);
  }
  vec3 c = base * (uAmbient + uIntensity * diffuse * falloff) + vec3(uSpecular * highlight * falloff * 2.0);
  vec2 centre = 0.5 * uViewport;
  float r = length(gl_FragCoord.xy - centre) / length(centre);
  c *= 1.0 - uVignette * smoothstep(0.45, 1.0, r);
  gl_FragColor = vec4(c, 1.0);
}
)";

// The same light computed per vertex (Gouraud), for large smooth surfaces such as the
// cavity wall that cover much of the image: the fragment shader then only applies the
// vignette, which makes such a surface several times cheaper to fill in software (llvmpipe).
const char* kVertexLitShader = R"(#version 120
uniform float uIntensity, uRange, uAmbient;
uniform float uSpecular, uShininess;
void main() {
  vec4 eye = gl_ModelViewMatrix * gl_Vertex;
  float d = length(eye.xyz);
  vec3 l = -eye.xyz / max(d, 1e-6);
  vec3 n = normalize(gl_NormalMatrix * gl_Normal);
  if (dot(n, l) < 0.0) n = -n;
  float falloff = 1.0 / (1.0 + (d / uRange) * (d / uRange));
  float diffuse = max(dot(n, l), 0.0);
  float highlight = pow(diffuse, uShininess);
  vec3 c = gl_Color.rgb * (uAmbient + uIntensity * diffuse * falloff) + vec3(uSpecular * highlight * falloff * 2.0);
  gl_FrontColor = vec4(c, 1.0);
  gl_Position = gl_ProjectionMatrix * eye;
}
)";

const char* kVignetteShader = R"(#version 120
uniform float uVignette;
uniform vec2 uViewport;
void main() {
  vec2 centre = 0.5 * uViewport;
  float r = length(gl_FragCoord.xy - centre) / length(centre);
  gl_FragColor = vec4(gl_Color.rgb * (1.0 - uVignette * smoothstep(0.45, 1.0, r)), 1.0);
}
)";

// Compiles one shader; 0 (and the log on stderr) when it fails.
GLuint compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  char log[1024] = "";
  glGetShaderInfoLog(shader, sizeof log, nullptr, log);
  std::fprintf(stderr, "OffscreenRenderer: shader compile failed, using fixed-function lighting: %s\n", log);
  glDeleteShader(shader);
  return 0;
}

}  // namespace

Material wetTissue() { return Material{0.55f, 60.0f, 0.35f, 400.0f}; }
Material cavityWall() {
  Material m{0.12f, 12.0f, 0.0f, 120.0f};
  m.perVertex = true;
  return m;
}
Material steel() { return Material{0.7f, 40.0f, 0.0f, 400.0f}; }

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
  buildProgram();
  setCamera(camera_);
}

namespace {

// Links a program from two shader sources; 0 when anything fails (said on stderr).
GLuint linkProgram(const char* vertex, const char* fragment) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
  if (!vs || !fs) {
    if (vs) glDeleteShader(vs);
    if (fs) glDeleteShader(fs);
    return 0;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_TRUE) return program;
  std::fprintf(stderr, "OffscreenRenderer: shader link failed, using fixed-function lighting\n");
  glDeleteProgram(program);
  return 0;
}

}  // namespace

void OffscreenRenderer::buildProgram() {
  if (!glGetString(GL_SHADING_LANGUAGE_VERSION)) return;  // no GLSL: fixed function
  const GLuint pixel = linkProgram(kVertexShader, kFragmentShader);
  const GLuint vertex = pixel ? linkProgram(kVertexLitShader, kVignetteShader) : 0;
  if (!vertex) {
    if (pixel) glDeleteProgram(pixel);
    return;
  }
  program_ = pixel;
  vertexProgram_ = vertex;
}

void OffscreenRenderer::applyMaterial(const Eigen::Isometry3d& model) {
  if (!program_) {
    const GLfloat spec[] = {material_.specular, material_.specular, material_.specular, 1.0f};
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, spec);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, std::min(128.0f, material_.shininess));
    return;
  }
  const GLuint p = material_.perVertex ? vertexProgram_ : program_;
  glUseProgram(p);
  const Eigen::Matrix4f m = model.matrix().cast<float>();
  if (!material_.perVertex) glUniformMatrix4fv(glGetUniformLocation(p, "uModel"), 1, GL_FALSE, m.data());
  glUniform1f(glGetUniformLocation(p, "uSpecular"), material_.specular);
  glUniform1f(glGetUniformLocation(p, "uShininess"), material_.shininess);
  glUniform1f(glGetUniformLocation(p, "uTexture"), material_.texture);
  glUniform1f(glGetUniformLocation(p, "uTextureScale"), material_.textureScale);
}

OffscreenRenderer::~OffscreenRenderer() {
  if (context_->gl) {
    if (program_) {
      makeCurrent();
      glUseProgram(0);
      glDeleteProgram(program_);
      glDeleteProgram(vertexProgram_);
    }
    OSMesaDestroyContext(context_->gl);
  }
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
  material_ = Material{};
  for (const GLuint p : {program_, vertexProgram_}) {
    if (!p) continue;
    glUseProgram(p);
    glUniform1f(glGetUniformLocation(p, "uIntensity"), float(lighting_.intensity));
    glUniform1f(glGetUniformLocation(p, "uRange"), float(lighting_.range));
    glUniform1f(glGetUniformLocation(p, "uAmbient"), float(lighting_.ambient));
    glUniform1f(glGetUniformLocation(p, "uVignette"), float(lighting_.vignette));
    glUniform2f(glGetUniformLocation(p, "uViewport"), float(width_), float(height_));
  }
}

void OffscreenRenderer::loadModel(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix4d m = viewMatrix() * pose.matrix();
  glLoadMatrixd(m.data());
  applyMaterial(pose);
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

void OffscreenRenderer::sphereStrip(const Eigen::Vector3d& radii, bool inward) {
  const int segments = inward ? kCavitySegments : kSegments, rings = segments / 2;
  const double sign = inward ? -1.0 : 1.0;
  for (int i = 0; i < rings; ++i) {
    const double t0 = M_PI * i / rings, t1 = M_PI * (i + 1) / rings;
    glBegin(GL_QUAD_STRIP);
    for (int j = 0; j <= segments; ++j) {
      const double p = sign * 2.0 * M_PI * j / segments;  // inward: the other winding
      for (double t : {t0, t1}) {
        const Eigen::Vector3d u(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
        // The ellipsoid's normal: the gradient of sum (x_i / r_i)^2.
        const Eigen::Vector3d n = sign * u.cwiseQuotient(radii).normalized();
        glNormal3d(n.x(), n.y(), n.z());
        glVertex3d(radii.x() * u.x(), radii.y() * u.y(), radii.z() * u.z());
      }
    }
    glEnd();
  }
}

void OffscreenRenderer::drawSphere(const Eigen::Isometry3d& pose, double radius, const Rgb& c) {
  loadModel(pose);
  color(c);
  sphereStrip(Eigen::Vector3d::Constant(radius), false);
}

void OffscreenRenderer::drawCavity(const Eigen::Vector3d& centre, const Eigen::Vector3d& radii, const Rgb& c) {
  if (!(radii.minCoeff() > 0.0) || !radii.allFinite() || !centre.allFinite())
    throw std::invalid_argument("OffscreenRenderer::drawCavity: expected a finite centre and positive radii");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = centre;
  loadModel(pose);
  color(c);
  sphereStrip(radii, true);
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
