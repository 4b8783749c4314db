// The group laws every Lie group of ldsm obeys, as one typed test over SO(3), SE(3) and Sim(3):
// composition and inverse agree with the matrices, the action is a group action, exp and log are
// inverse, hat and vee are inverse and the small adjoint is the Lie bracket, the adjoint
// conjugates exponentials, the composition assignment operator, and the float instantiation
// agrees with double (at the singular and switching angles too). What is particular to one group
// (constructions, embeddings, Jacobians) stays in so3_test, se3_test and sim3_test.
#include <gtest/gtest.h>

#include <algorithm>

#include "lie_test_utils.h"
#include "math/se3.h"
#include "math/sim3.h"
#include "math/so3.h"

namespace ldsm {
namespace {

using test::maxAbsDiff;
using test::TestRandom;

/// Random elements and tangents of each group, with the accuracy its arithmetic allows.
template <typename G>
struct GroupTraits;

/// How far the float instantiation may stray from double (times test::kFloatSlack): the matrix,
/// the log, the action on a point, the Jacobians, and a double element cast to float.
struct FloatTolerance {
  double matrix, log, action, jacobian, cast;
};

template <>
struct GroupTraits<SO3d> {
  static SO3d::Tangent tangent(TestRandom& r, double max_angle) {
    return r.rotationVector(0, max_angle);
  }
  /// A tangent of rotation angle `angle` (and log-scale `sigma`, Sim(3) only).
  static SO3d::Tangent tangentAt(TestRandom& r, double angle, double /*sigma*/) {
    return r.rotationVector(angle, angle);
  }
  static double tolerance() { return 1e-14; }
  /// The small adjoint ad(x) (y -> vee([hat x, hat y])): for so(3) the hat itself.
  static Eigen::Matrix3d ad(const SO3d::Tangent& x) { return SO3d::hat(x); }
  static FloatTolerance floatTolerance() { return {1e-6, 2e-6, 1e-6, 2e-6, 1e-6}; }
  static double floatJacobianError(const SO3d::Tangent& w) {
    return std::max(
        maxAbsDiff(SO3f::leftJacobianInverse(w.cast<float>()), SO3d::leftJacobianInverse(w)),
        maxAbsDiff(SO3f::rightJacobian(w.cast<float>()), SO3d::rightJacobian(w)));
  }
};

template <>
struct GroupTraits<SE3d> {
  static SE3d::Tangent tangent(TestRandom& r, double max_angle) {
    SE3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(0, max_angle);
    return x;
  }
  static SE3d::Tangent tangentAt(TestRandom& r, double angle, double /*sigma*/) {
    SE3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(angle, angle);
    return x;
  }
  static double tolerance() { return 1e-13; }
  static SE3d::Adjoint ad(const SE3d::Tangent& x) { return SE3d::ad(x); }
  static FloatTolerance floatTolerance() { return {2e-6, 1e-5, 1e-5, 1e-5, 1e-6}; }
  static double floatJacobianError(const SE3d::Tangent& x) {
    return maxAbsDiff(SE3f::leftJacobianInverse(x.cast<float>()), SE3d::leftJacobianInverse(x));
  }
};

template <>
struct GroupTraits<Sim3d> {
  static Sim3d::Tangent tangent(TestRandom& r, double max_angle) {
    Sim3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(0, max_angle), r.uniform(-1.0, 1.0);
    return x;
  }
  static Sim3d::Tangent tangentAt(TestRandom& r, double angle, double sigma) {
    Sim3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(angle, angle), sigma;
    return x;
  }
  static double tolerance() { return 1e-12; }
  static Sim3d::Adjoint ad(const Sim3d::Tangent& x) { return Sim3d::ad(x); }
  static FloatTolerance floatTolerance() { return {5e-6, 2e-5, 2e-5, 0.0, 2e-6}; }
  static double floatJacobianError(const Sim3d::Tangent&) { return 0.0; }  // none in float
};

/// The matrix acting on homogeneous points (SO3: the rotation itself).
template <typename G>
auto asMatrix(const G& g) {
  return g.matrix();
}

template <typename G>
class LieGroupLaws : public ::testing::Test {
 protected:
  using Traits = GroupTraits<G>;
  G randomElement(TestRandom& r, double max_angle = 3.0) {
    return G::exp(Traits::tangent(r, max_angle));
  }
};

using Groups = ::testing::Types<SO3d, SE3d, Sim3d>;
TYPED_TEST_SUITE(LieGroupLaws, Groups);

TYPED_TEST(LieGroupLaws, CompositionAndInverseAreTheMatrixOperations) {
  TestRandom rnd(101);
  const double tol = TestFixture::Traits::tolerance();
  for (int i = 0; i < 50; ++i) {
    const TypeParam A = this->randomElement(rnd);
    const TypeParam B = this->randomElement(rnd);
    EXPECT_LT(maxAbsDiff(asMatrix(A * B), asMatrix(A) * asMatrix(B)), tol);
    EXPECT_LT(maxAbsDiff(asMatrix(A.inverse()), asMatrix(A).inverse()), 10 * tol);
    EXPECT_LT(maxAbsDiff(asMatrix(A * A.inverse()), asMatrix(TypeParam())), tol);
    TypeParam C = A;
    C *= B;
    EXPECT_LT(maxAbsDiff(asMatrix(C), asMatrix(A * B)), 1e-15);
  }
}

TYPED_TEST(LieGroupLaws, TheActionOnPointsIsAGroupAction) {
  TestRandom rnd(102);
  const double tol = TestFixture::Traits::tolerance();
  for (int i = 0; i < 50; ++i) {
    const TypeParam A = this->randomElement(rnd);
    const TypeParam B = this->randomElement(rnd);
    const Eigen::Vector3d p = rnd.vector<3>(5.0);
    EXPECT_LT(maxAbsDiff((A * B) * p, A * (B * p)), 10 * tol);
    EXPECT_LT(maxAbsDiff(A.inverse() * (A * p), p), 10 * tol);
    EXPECT_LT(maxAbsDiff(TypeParam() * p, p), 1e-15);
  }
}

TYPED_TEST(LieGroupLaws, LogInvertsExpBelowPi) {
  TestRandom rnd(103);
  const double tol = TestFixture::Traits::tolerance();
  for (int i = 0; i < 50; ++i) {
    const typename TypeParam::Tangent x = TestFixture::Traits::tangent(rnd, 3.0);
    EXPECT_LT(maxAbsDiff(TypeParam::exp(x).log(), x), 100 * tol);
    const TypeParam A = this->randomElement(rnd);
    EXPECT_LT(maxAbsDiff(asMatrix(TypeParam::exp(A.log())), asMatrix(A)), 10 * tol);
  }
  EXPECT_LT(maxAbsDiff(TypeParam().log(), TypeParam::Tangent::Zero().eval()), 1e-15);
}

TYPED_TEST(LieGroupLaws, HatAndVeeAreInverseAndTheSmallAdjointIsTheLieBracket) {
  TestRandom rnd(104);
  for (int i = 0; i < 20; ++i) {
    const typename TypeParam::Tangent x = TestFixture::Traits::tangent(rnd, 1.0);
    const typename TypeParam::Tangent y = TestFixture::Traits::tangent(rnd, 1.0);
    EXPECT_LT(maxAbsDiff(TypeParam::vee(TypeParam::hat(x)), x), 1e-15);
    const auto X = TypeParam::hat(x);
    const auto Y = TypeParam::hat(y);
    EXPECT_LT(maxAbsDiff(TestFixture::Traits::ad(x) * y, TypeParam::vee(X * Y - Y * X)), 1e-15);
  }
}

TYPED_TEST(LieGroupLaws, TheAdjointConjugatesExponentials) {
  TestRandom rnd(105);
  const double tol = TestFixture::Traits::tolerance();
  for (int i = 0; i < 50; ++i) {
    const TypeParam T = this->randomElement(rnd);
    const typename TypeParam::Tangent x = TestFixture::Traits::tangent(rnd, 1.5);
    EXPECT_LT(maxAbsDiff(asMatrix(TypeParam::exp(T.adjoint() * x)),
                         asMatrix(T * TypeParam::exp(x) * T.inverse())),
              10 * tol);
  }
}

TYPED_TEST(LieGroupLaws, FloatAgreesWithDouble) {
  TestRandom rnd(106);
  for (int i = 0; i < 20; ++i) {
    const TypeParam A = this->randomElement(rnd);
    const TypeParam B = this->randomElement(rnd);
    const auto Af = A.template cast<float>();
    const auto Bf = B.template cast<float>();
    EXPECT_LT(maxAbsDiff(asMatrix(Af * Bf), asMatrix(A * B)), 2e-5 * test::kFloatSlack);
    const Eigen::Vector3f p = rnd.vector<3>(2.0).template cast<float>();
    EXPECT_LT(maxAbsDiff(Af * p, A * p.cast<double>()), 2e-5 * test::kFloatSlack);
  }
}

TYPED_TEST(LieGroupLaws, FloatAgreesWithDoubleAtSingularAndSwitchingAngles) {
  using Traits = typename TestFixture::Traits;
  using Float = decltype(TypeParam().template cast<float>());
  TestRandom rnd(107);
  const FloatTolerance tol = Traits::floatTolerance();
  const double slack = test::kFloatSlack;
  for (double angle : {0.0, 1e-8, 1e-4, 0.01, 0.3, 2.0, 3.1}) {
    for (double sigma : {0.0, 1e-9, 0.5}) {
      const typename TypeParam::Tangent x = Traits::tangentAt(rnd, angle, sigma);
      const TypeParam Td = TypeParam::exp(x);
      const Float Tf = Float::exp(x.template cast<float>());
      const Eigen::Vector3d p = rnd.vector<3>(2.0);
      EXPECT_LT(maxAbsDiff(asMatrix(Tf), asMatrix(Td)), slack * tol.matrix)
          << angle << " " << sigma;
      EXPECT_LT(maxAbsDiff(Tf.log(), Td.log()), slack * tol.log) << angle << " " << sigma;
      EXPECT_LT(maxAbsDiff(Tf * p.cast<float>(), Td * p), slack * tol.action) << angle;
      EXPECT_LE(Traits::floatJacobianError(x), slack * tol.jacobian) << angle;
      EXPECT_LT(maxAbsDiff(asMatrix(Td.template cast<float>()), asMatrix(Td)), slack * tol.cast);
    }
  }
}

}  // namespace
}  // namespace ldsm
