#pragma once
// Fibre frames beyond one global frame ("Adamss: Advanced Anisotropic Mass-Spring System",
// Secs. 2.3 and 2.8.1): the anisotropy axes of every element (fibre, sheet, sheet-normal) from
// spherical angles, from a fibre and a sheet vector, from a file with one row per element, or
// from a transmural rotation that turns the fibre about the wall normal linearly through the
// wall, as the fibre angle of the myocardium does (about +60 degrees at the inner face to -60
// at the outer one). A frame has orthonormal, right-handed columns (fibre, sheet, sheet-normal).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "tissue_trainer/core/mesh/generators.h"

namespace tt {

// The global frame turned by the spherical angles phi, theta (degrees) of Sec. 2.8.1: fibre
// (sin t cos p, sin t sin p, cos t), sheet its derivative in t (cos t cos p, cos t sin p,
// -sin t), sheet-normal fibre x sheet.
Eigen::Matrix3d fibreFrameFromAngles(double phiDeg, double thetaDeg);

// Why fibreFrameFromVectors refused its input.
enum class FrameProblem { kNone, kZeroFibre, kZeroSheet, kParallel };

// The frame (fibre, sheet, fibre x sheet) of a fibre and a sheet vector of any length: the sheet
// loses its component along the fibre. Refuses a zero or non-finite vector and a sheet whose
// part orthogonal to the fibre is below 1e-6 of its length (parallel).
FrameProblem fibreFrameFromVectors(const Eigen::Vector3d& fibre, const Eigen::Vector3d& sheet,
                                   Eigen::Matrix3d& frame);

// One frame per element from a text file, in element order (tets, then hexes). Each row is
// either 6 numbers (fibre x y z, sheet x y z) or 2 (phi theta in degrees, as
// fibreFrameFromAngles); blank lines and everything after '#' are skipped. Throws InputError
// "FILE:LINE: ..." for a row that is not 2 or 6 numbers, a zero or parallel pair, or a number of
// rows other than `elements`.
std::vector<Eigen::Matrix3d> readFibreFile(const std::string& path, int elements);

// The fibre turned about the unit wall normal n by an angle that varies linearly with the wall
// position s = n . x, from angleFrom at s = from to angleTo at s = to (held beyond them):
//   fibre        f = cos(a) r + sin(a) (n x r)   (r: the fibre at angle 0, in the wall plane)
//   sheet        n                              (the transmural direction)
//   sheet-normal f x n
// A positive angle turns r towards n x r (right-handed about n).
struct TransmuralFibres {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();     // unit
  Eigen::Vector3d reference = Eigen::Vector3d::UnitZ();  // unit, orthogonal to normal
  double from = 0.0, to = 1.0;                           // wall positions, from < to (m)
  double angleFrom = 0.0, angleTo = 0.0;                 // rad

  // The fibre angle at point p (rad).
  double angleAt(const Eigen::Vector3d& p) const;
  Eigen::Matrix3d frameAt(const Eigen::Vector3d& p) const;
};

// The fibres of the truncated prolate-spheroidal ventricle of truncatedEllipsoid, in its own
// coordinates (long axis z, apex towards -z). The transmural coordinate t of a point is that of
// the generator's spheroid through it,
//   (x^2 + y^2) / r_s(t)^2 + z^2 / r_l(t)^2 = 1,   r_s, r_l linear in t as in EllipsoidShape,
// 0 on the endocardium, 1 on the epicardium (held there inside and outside the wall). With
//   n  the outward unit normal of that spheroid (its function's gradient),
//   c  = (-y, x, 0) / |(x, y)|, circumferential (on the long axis: a unit vector orthogonal to n),
//   l  = n x c, longitudinal (towards the base on the lateral wall),
//   a  = angleEndo + t (angleEpi - angleEndo),
// the frame is fibre f = cos(a) c + sin(a) l, sheet n, sheet-normal f x n.
struct EllipsoidFibres {
  EllipsoidShape shape;
  double angleEndo = 0.0, angleEpi = 0.0;  // rad

  double transmuralAt(const Eigen::Vector3d& p) const;
  // The outward unit normal of the spheroid of transmural coordinate t at p.
  Eigen::Vector3d normalAt(const Eigen::Vector3d& p, double t) const;
  Eigen::Vector3d circumferentialAt(const Eigen::Vector3d& p, const Eigen::Vector3d& normal) const;
  Eigen::Matrix3d frameAt(const Eigen::Vector3d& p) const;
};

}  // namespace tt
