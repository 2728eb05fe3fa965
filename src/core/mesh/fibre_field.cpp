#include "tissue_trainer/core/mesh/fibre_field.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "text_scanner.h"

namespace tt {

Eigen::Matrix3d fibreFrameFromAngles(double phiDeg, double thetaDeg) {
  const double p = phiDeg * M_PI / 180.0, t = thetaDeg * M_PI / 180.0;
  Eigen::Matrix3d frame;
  frame.col(0) << std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t);
  frame.col(1) << std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), -std::sin(t);
  frame.col(2) = frame.col(0).cross(frame.col(1));
  return frame;
}

FrameProblem fibreFrameFromVectors(const Eigen::Vector3d& fibre, const Eigen::Vector3d& sheet,
                                   Eigen::Matrix3d& frame) {
  const double fibreLength = fibre.norm(), sheetLength = sheet.norm();
  if (!(fibreLength > 0.0) || !std::isfinite(fibreLength)) return FrameProblem::kZeroFibre;
  if (!(sheetLength > 0.0) || !std::isfinite(sheetLength)) return FrameProblem::kZeroSheet;
  const Eigen::Vector3d f = fibre / fibreLength;
  const Eigen::Vector3d s = sheet / sheetLength - (sheet / sheetLength).dot(f) * f;
  if (!(s.norm() > 1e-6)) return FrameProblem::kParallel;
  frame << f, s.normalized(), f.cross(s.normalized());
  return FrameProblem::kNone;
}

std::vector<Eigen::Matrix3d> readFibreFile(const std::string& path, int elements) {
  const std::string text = meshio::loadTextFile(path);
  meshio::Scanner scan(path, text, '#');
  const std::string expectedRows =
      "expected " + std::to_string(elements) + " rows (one per element: tets, then hexes)";
  std::vector<Eigen::Matrix3d> frames;
  long lastLine = 1;
  while (scan.nextLine()) {
    lastLine = scan.lineNo();
    if (static_cast<int>(frames.size()) == elements) scan.fail(expectedRows + ", found more");
    double v[6];
    const std::size_t n = scan.size();
    if (n != 6 && n != 2)
      scan.fail("expected 6 numbers (fibre x y z, sheet x y z) or 2 angles (phi theta, degrees), "
                "got " + std::to_string(n) + " values");
    for (std::size_t i = 0; i < n; ++i) v[i] = scan.toDouble(scan[i], "a number");
    if (n == 2) {
      frames.push_back(fibreFrameFromAngles(v[0], v[1]));
      continue;
    }
    Eigen::Matrix3d frame;
    switch (fibreFrameFromVectors({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, frame)) {
      case FrameProblem::kZeroFibre: scan.fail("expected a non-zero fibre vector");
      case FrameProblem::kZeroSheet: scan.fail("expected a non-zero sheet vector");
      case FrameProblem::kParallel: scan.fail("expected a sheet vector not parallel to the fibre");
      case FrameProblem::kNone: break;
    }
    frames.push_back(frame);
  }
  if (static_cast<int>(frames.size()) != elements)
    scan.failAt(lastLine, expectedRows + ", the file ends after " +
                              std::to_string(frames.size()));
  return frames;
}

double TransmuralFibres::angleAt(const Eigen::Vector3d& p) const {
  const double depth = std::clamp((normal.dot(p) - from) / (to - from), 0.0, 1.0);
  return angleFrom + depth * (angleTo - angleFrom);
}

Eigen::Matrix3d TransmuralFibres::frameAt(const Eigen::Vector3d& p) const {
  const double a = angleAt(p);
  const Eigen::Vector3d fibre = std::cos(a) * reference + std::sin(a) * normal.cross(reference);
  Eigen::Matrix3d frame;
  frame << fibre, normal, fibre.cross(normal);
  return frame;
}

namespace {

// (x^2 + y^2) / r_s(t)^2 + z^2 / r_l(t)^2 - 1: decreasing in t, since both radii grow with t.
double spheroidLevel(const EllipsoidShape& s, const Eigen::Vector3d& p, double t) {
  const double rs = s.shortRadiusAt(t), rl = s.longRadiusAt(t);
  return (p.x() * p.x() + p.y() * p.y()) / (rs * rs) + p.z() * p.z() / (rl * rl) - 1.0;
}

}  // namespace

double EllipsoidFibres::transmuralAt(const Eigen::Vector3d& p) const {
  if (spheroidLevel(shape, p, 0.0) <= 0.0) return 0.0;
  if (spheroidLevel(shape, p, 1.0) >= 0.0) return 1.0;
  double inside = 0.0, outside = 1.0;  // the level is > 0 at `inside`, < 0 at `outside`
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (inside + outside);
    (spheroidLevel(shape, p, mid) > 0.0 ? inside : outside) = mid;
  }
  return 0.5 * (inside + outside);
}

Eigen::Vector3d EllipsoidFibres::normalAt(const Eigen::Vector3d& p, double t) const {
  const double rs = shape.shortRadiusAt(t), rl = shape.longRadiusAt(t);
  return Eigen::Vector3d(p.x() / (rs * rs), p.y() / (rs * rs), p.z() / (rl * rl)).normalized();
}

Eigen::Vector3d EllipsoidFibres::circumferentialAt(const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d around(-p.y(), p.x(), 0.0);
  if (around.norm() > 1e-9 * shape.epiLong) return around.normalized();
  const Eigen::Vector3d helper =
      std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return (helper - helper.dot(normal) * normal).normalized();
}

Eigen::Matrix3d EllipsoidFibres::frameAt(const Eigen::Vector3d& p) const {
  const double t = transmuralAt(p);
  const Eigen::Vector3d n = normalAt(p, t);
  const Eigen::Vector3d c = circumferentialAt(p, n);
  const Eigen::Vector3d l = n.cross(c);
  const double a = angleEndo + t * (angleEpi - angleEndo);
  const Eigen::Vector3d fibre = std::cos(a) * c + std::sin(a) * l;
  Eigen::Matrix3d frame;
  frame << fibre, n, fibre.cross(n);
  return frame;
}

}  // namespace tt
