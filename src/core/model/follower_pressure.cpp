#include "tissue_trainer/core/model/follower_pressure.h"

#include <utility>

namespace tt {
namespace {

Eigen::Matrix3d followerSkew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Vector3d areaVector(const Eigen::VectorXd& x, const FollowerPressureModel::Face& face) {
  const Eigen::Vector3d a = x.segment<3>(3 * face[0]);
  return 0.5 * (x.segment<3>(3 * face[1]) - a).cross(x.segment<3>(3 * face[2]) - a);
}

}  // namespace

FollowerPressureModel::FollowerPressureModel(std::vector<Face> faces, double pressure)
    : faces_(std::move(faces)), pressure_(pressure) {}

FollowerPressureModel::FollowerPressureModel(std::vector<Face> faces, const TimeCurve& pressure)
    : faces_(std::move(faces)), pressure_(pressure.value(0.0)), followsCurve_(true),
      curve_(pressure) {}

void FollowerPressureModel::beginStep(double t, const Eigen::VectorXd&, const Eigen::VectorXd&) {
  if (followsCurve_) pressure_ = curve_.value(t);
}

double FollowerPressureModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                       Eigen::VectorXd& f) const {
  for (const Face& face : faces_) {
    const Eigen::Vector3d load = (-pressure_ / 3.0) * areaVector(x, face);
    for (int node : face) f.segment<3>(3 * node) += load;
  }
  return 0.0;
}

Eigen::Matrix<double, 9, 9> FollowerPressureModel::faceJacobian(const Eigen::VectorXd& x,
                                                               const Face& face,
                                                               double pressure) {
  Eigen::Matrix<double, 9, 9> K;
  for (int j = 0; j < 3; ++j) {
    // da/dx_j = [x_prev - x_next]x / 2 in the cyclic order of the face.
    const Eigen::Vector3d edge =
        x.segment<3>(3 * face[(j + 2) % 3]) - x.segment<3>(3 * face[(j + 1) % 3]);
    const Eigen::Matrix3d block = (-pressure / 6.0) * followerSkew(edge);
    for (int i = 0; i < 3; ++i) K.block<3, 3>(3 * i, 3 * j) = block;
  }
  return K;
}

void FollowerPressureModel::addStiffnessBlocks(const Eigen::VectorXd& x, double scale,
                                               bool symmetric, const SparsePattern& pattern,
                                               SparseMatrix& K) const {
  for (const Face& face : faces_) {
    Eigen::Matrix<double, 9, 9> Ke = scale * faceJacobian(x, face, pressure_);
    if (symmetric) Ke = (0.5 * (Ke + Ke.transpose())).eval();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        pattern.addNodeBlock(K, face[i], face[j], Ke.block<3, 3>(3 * i, 3 * j));
  }
}

void FollowerPressureModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                         const SparsePattern& pattern, SparseMatrix& K) const {
  addStiffnessBlocks(x, scale, true, pattern, K);
}

void FollowerPressureModel::addExactStiffness(const Eigen::VectorXd& x, double scale,
                                              const SparsePattern& pattern,
                                              SparseMatrix& K) const {
  addStiffnessBlocks(x, scale, false, pattern, K);
}

void FollowerPressureModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                              double scale, Eigen::VectorXd& out) const {
  for (const Face& face : faces_) {
    Eigen::Matrix<double, 9, 9> Ke = faceJacobian(x, face, pressure_);
    Ke = (0.5 * scale) * (Ke + Ke.transpose()).eval();
    Eigen::Matrix<double, 9, 1> de;
    for (int i = 0; i < 3; ++i) de.segment<3>(3 * i) = d.segment<3>(3 * face[i]);
    const Eigen::Matrix<double, 9, 1> product = Ke * de;
    for (int i = 0; i < 3; ++i) out.segment<3>(3 * face[i]) += product.segment<3>(3 * i);
  }
}

}  // namespace tt
