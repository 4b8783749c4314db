// The group laws every Lie group of ldsm obeys, as one typed test over SO(3), SE(3) and Sim(3):
// composition and inverse agree with the matrices, the action is a group action, exp and log are
// inverse, the adjoint conjugates exponentials, the composition assignment operator, and the
// float instantiation agrees with double. What is particular to one group (constructions,
// embeddings, Jacobians) stays in so3_test, se3_test and sim3_test.
#include <gtest/gtest.h>

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

template <>
struct GroupTraits<SO3d> {
  static SO3d::Tangent tangent(TestRandom& r, double max_angle) {
    return r.rotationVector(0, max_angle);
  }
  static double tolerance() { return 1e-14; }
};

template <>
struct GroupTraits<SE3d> {
  static SE3d::Tangent tangent(TestRandom& r, double max_angle) {
    SE3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(0, max_angle);
    return x;
  }
  static double tolerance() { return 1e-13; }
};

template <>
struct GroupTraits<Sim3d> {
  static Sim3d::Tangent tangent(TestRandom& r, double max_angle) {
    Sim3d::Tangent x;
    x << r.vector<3>(2.0), r.rotationVector(0, max_angle), r.uniform(-1.0, 1.0);
    return x;
  }
  static double tolerance() { return 1e-12; }
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

TYPED_TEST(LieGroupLaws, HatAndVeeAreInverse) {
  TestRandom rnd(104);
  const typename TypeParam::Tangent x = TestFixture::Traits::tangent(rnd, 1.0);
  EXPECT_LT(maxAbsDiff(TypeParam::vee(TypeParam::hat(x)), x), 1e-16);
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

}  // namespace
}  // namespace ldsm
