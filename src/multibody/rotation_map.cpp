// The three placements R(q) and their partials (see rotation_map.hpp).
#include "rigidae/multibody/rotation_map.hpp"

#include "../coords/coordinate_maps.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/model/scene.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae::multibody {

namespace {

class QuaternionMap final : public RotationMap {
 public:
  QuaternionMap() {
    for (int m = 0; m < 4; ++m) {
      const std::array<Mat3, 4> Rk = coords::quaternion_placement_partials(Vec4::Unit(m));
      for (int k = 0; k < 4; ++k) second_[k][m] = Rk[k];
    }
  }
  int nq() const override { return 4; }
  void evaluate(const double* q, int order, RotationPartials& out) const override {
    const Vec4 qq(q[0], q[1], q[2], q[3]);
    out.nq = 4;
    out.R = so3::quaternion_to_matrix(qq);
    const std::array<Mat3, 4> Rk = coords::quaternion_placement_partials(qq);
    for (int k = 0; k < 4; ++k) out.d1[k] = Rk[k];
    if (order >= 2)
      for (int k = 0; k < 4; ++k)
        for (int m = 0; m < 4; ++m) out.d2[k][m] = second_[k][m];
    out.d2_zero = false;
    out.d3_zero = true;
  }

 private:
  std::array<std::array<Mat3, 4>, 4> second_;
};

class LinearMap final : public RotationMap {
 public:
  int nq() const override { return 9; }
  void evaluate(const double* q, int /*order*/, RotationPartials& out) const override {
    out.nq = 9;
    out.R << q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7], q[8];
    for (int k = 0; k < 9; ++k) {
      out.d1[k].setZero();
      out.d1[k](k / 3, k % 3) = 1.0;
    }
    out.d2_zero = true;
    out.d3_zero = true;
  }
};

class EulerMap final : public RotationMap {
 public:
  explicit EulerMap(const so3::EulerSequence& seq) : seq_(seq) {}
  int nq() const override { return 3; }
  void set_sequence(const so3::EulerSequence& seq) override { seq_ = seq; }
  void evaluate(const double* q, int order, RotationPartials& out) const override {
    out.nq = 3;
    // F[f][n] = (elementary rotation f) * hat(axis)^n, n = 0..3.
    std::array<std::array<Mat3, 4>, 3> F;
    for (int f = 0; f < 3; ++f) {
      const Mat3 H = so3::hat(Vec3::Unit(seq_.axes[f]));
      F[f][0] = so3::axis_rotation(seq_.axes[f], q[f]);
      for (int n = 1; n <= 3; ++n) F[f][n] = F[f][n - 1] * H;
    }
    const auto partial = [&](int n0, int n1, int n2) -> Mat3 { return F[0][n0] * F[1][n1] * F[2][n2]; };
    out.R = partial(0, 0, 0);
    for (int k = 0; k < 3; ++k) out.d1[k] = partial(k == 0, k == 1, k == 2);
    out.d2_zero = false;
    out.d3_zero = false;
    if (order >= 2)
      for (int k = 0; k < 3; ++k)
        for (int m = 0; m < 3; ++m) out.d2[k][m] = partial((k == 0) + (m == 0), (k == 1) + (m == 1), (k == 2) + (m == 2));
    if (order >= 3)
      for (int k = 0; k < 3; ++k)
        for (int m = 0; m < 3; ++m)
          for (int n = 0; n < 3; ++n)
            out.d3[k][m][n] = partial((k == 0) + (m == 0) + (n == 0), (k == 1) + (m == 1) + (n == 1),
                                      (k == 2) + (m == 2) + (n == 2));
  }

 private:
  so3::EulerSequence seq_;
};

}  // namespace

std::unique_ptr<RotationMap> make_rotation_map(const Coordinates& c, const so3::EulerSequence& seq) {
  // One row per registered coordinates (coords/registry.cpp) that multibody
  // scenes can use.
  struct Entry {
    const Coordinates& coordinates;
    std::unique_ptr<RotationMap> (*make)(const so3::EulerSequence&);
  };
  static const Entry kMaps[] = {
      {Coordinates::Quaternion, [](const so3::EulerSequence&) -> std::unique_ptr<RotationMap> {
         return std::make_unique<QuaternionMap>();
       }},
      {Coordinates::Linear,
       [](const so3::EulerSequence&) -> std::unique_ptr<RotationMap> { return std::make_unique<LinearMap>(); }},
      {Coordinates::EulerAngles,
       [](const so3::EulerSequence& s) -> std::unique_ptr<RotationMap> { return std::make_unique<EulerMap>(s); }},
  };
  for (const Entry& e : kMaps)
    if (e.coordinates == c) return e.make(seq);
  throw InputError("coordinates '" + c.name() + "' have no rotation map for multibody scenes (src/multibody/rotation_map.cpp)");
}

}  // namespace rigidae::multibody
