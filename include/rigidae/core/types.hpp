#pragma once
// Small fixed-size linear-algebra vocabulary shared by every module.
//
// The largest model rigidae assembles is a rotation in linear coordinates:
// 9 coordinates, 9 velocities, 6 position constraints. Vectors whose size
// depends on the representation are Eigen "dynamic with a maximum" types:
// they live on the stack, so the residual never touches the heap.
#include <limits>

#include <Eigen/Dense>

namespace rigidae {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;

// "Not computed" in records, summaries and accuracy tables.
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline constexpr int kMaxCoordinates = 9;  // nq
inline constexpr int kMaxVelocities = 9;   // nv
inline constexpr int kMaxConstraints = 6;  // nc

template <int MaxRows>
using BoundedVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, MaxRows, 1>;
template <int MaxRows, int MaxCols>
using BoundedMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, MaxRows, MaxCols>;

using VecQ = BoundedVec<kMaxCoordinates>;
using VecV = BoundedVec<kMaxVelocities>;
using VecC = BoundedVec<kMaxConstraints>;
using MatVV = BoundedMat<kMaxVelocities, kMaxVelocities>;
using MatCQ = BoundedMat<kMaxConstraints, kMaxCoordinates>;
using MatCV = BoundedMat<kMaxConstraints, kMaxVelocities>;
using MatQQ = BoundedMat<kMaxCoordinates, kMaxCoordinates>;
using MatQV = BoundedMat<kMaxCoordinates, kMaxVelocities>;
using MatVQ = BoundedMat<kMaxVelocities, kMaxCoordinates>;

// The largest DAE: q, v, and two multiplier groups (GGL in linear coordinates).
inline constexpr int kMaxUnknowns = kMaxCoordinates + kMaxVelocities + 2 * kMaxConstraints;

}  // namespace rigidae
