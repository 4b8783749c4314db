#include "frontend/initializer_hypotheses.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "ldsm/error.h"

namespace ldsm {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

double angleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0.0) || !(nb > 0.0)) return 180.0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0)) * kRadToDeg;
}

bool seesParallax(const CoarseInitializer& h) {
  return h.status() == InitStatus::kConfirming || h.status() == InitStatus::kComplete;
}

}  // namespace

Eigen::Vector3d InitializerHypotheses::seed(int i) {
  if (i <= 0 || i >= kMaxHypotheses) return Eigen::Vector3d::Zero();
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  s((i - 1) / 2) = (i % 2 == 1 ? 1.0 : -1.0) * kSeedLength;
  return s;
}

InitializerHypotheses::InitializerHypotheses(const PyramidCamera& camera,
                                             const CoarseInitializerSettings& settings,
                                             int hypotheses) {
  if (hypotheses < 1 || hypotheses > kMaxHypotheses) {
    throw ConfigError("initializer.hypotheses must be in [1, " + std::to_string(kMaxHypotheses) +
                      "] (got " + std::to_string(hypotheses) + ")");
  }
  members_.resize(static_cast<std::size_t>(hypotheses));
  alive_scratch_.reserve(static_cast<std::size_t>(hypotheses));
  // Only the first selects reference points; the others adopt them.
  CoarseInitializerSettings follower = settings;
  follower.use_pixel_selector = false;
  for (int i = 0; i < hypotheses; ++i) {
    members_[static_cast<std::size_t>(i)].initializer =
        std::make_unique<CoarseInitializer>(camera, i == 0 ? settings : follower);
  }
}

void InitializerHypotheses::reset() {
  for (std::size_t i = 0; i < members_.size(); ++i) {
    // The followers' copies of the reference are big (about 2 MB each at 1232x368); the map
    // needs that memory more once it exists.
    if (i == 0) {
      members_[i].initializer->reset();
    } else {
      members_[i].initializer->releaseMemory();
    }
    members_[i].alive = false;
    members_[i].restarted = false;
  }
  status_ = InitStatus::kNoReference;
  failure_ = InitFailure::kNone;
  frames_ = 0;
  leader_ = 0;
}

void InitializerHypotheses::releaseMemory() {
  reset();
  members_[0].initializer->releaseMemory();
}

int InitializerHypotheses::alive() const {
  int n = 0;
  for (const Member& m : members_) n += m.alive ? 1 : 0;
  return n;
}

const InitFrameStats& InitializerHypotheses::lastFrameStats() const {
  return members_[static_cast<std::size_t>(leader_)].initializer->lastFrameStats();
}

const InitializationResult& InitializerHypotheses::result() const {
  return members_[static_cast<std::size_t>(leader_)].initializer->result();
}

void InitializerHypotheses::startReference(const ImagePyramid& pyramid, double exposure) {
  reset();
  CoarseInitializer& primary = *members_.front().initializer;
  primary.addFrame(pyramid, exposure);  // becomes the reference (or fails: too few points)
  status_ = primary.status();
  failure_ = primary.failure();
  if (primary.failed()) return;
  members_.front().alive = true;
  for (std::size_t i = 1; i < members_.size(); ++i) {
    members_[i].initializer->adoptReference(primary, seed(static_cast<int>(i)));
    members_[i].alive = true;
  }
}

int InitializerHypotheses::bestAlive() const {
  // The lowest photometric energy (outliers at the cap) leads, unless a hypothesis that keeps
  // about as many points inliers (kComparableInliers) fits them clearly better (kClearlyBetterRms):
  // a motion in the wrong basin can bend the depths until more points pass as poor inliers,
  // which lowers its energy below the true motion's (on the corridor loop, 24 degrees off with
  // 1.6 degrees of yaw: energy 6 % lower, inlier RMS 5.98 against 4.50 grey levels).
  int by_energy = -1, by_rms = -1;
  double most_inliers = 0.0;
  for (const Member& m : members_)
    if (m.alive)
      most_inliers = std::max(most_inliers, m.initializer->lastFrameStats().good_fraction);
  const auto stats = [&](int i) -> const InitFrameStats& {
    return members_[static_cast<std::size_t>(i)].initializer->lastFrameStats();
  };
  const auto energy = [&](int i) {
    return members_[static_cast<std::size_t>(i)].initializer->photometricEnergy();
  };
  for (int i = 0; i < static_cast<int>(members_.size()); ++i) {
    if (!members_[static_cast<std::size_t>(i)].alive) continue;
    if (by_energy < 0 || energy(i) < energy(by_energy)) by_energy = i;
    if (stats(i).good_fraction >= kComparableInliers * most_inliers &&
        (by_rms < 0 || stats(i).rms_residual < stats(by_rms).rms_residual))
      by_rms = i;
  }
  // The leader keeps its lead against an energy only slightly lower: hypotheses in the two basins
  // of a sideways motion (translation one way and yaw against it, or the other way) can come
  // within 1 % of each other on one frame after the true one led by 10-25 % on every frame
  // before (all three calibration errors on the rendered loop, on aarch64's numerics).
  const bool leader_alive = leader_ >= 0 && leader_ < static_cast<int>(members_.size()) &&
                            members_[static_cast<std::size_t>(leader_)].alive;
  if (leader_alive && by_energy != leader_ && energy(by_energy) > kTakeOverEnergy * energy(leader_))
    by_energy = leader_;
  if (by_rms >= 0 && stats(by_rms).rms_residual < kClearlyBetterRms * stats(by_energy).rms_residual)
    return by_rms;
  return by_energy;
}

void InitializerHypotheses::dropDuplicates() {
  for (std::size_t i = 0; i < members_.size(); ++i) {
    for (std::size_t j = i + 1; j < members_.size(); ++j) {
      if (!members_[i].alive || !members_[j].alive) continue;
      const CoarseInitializer& a = *members_[i].initializer;
      const CoarseInitializer& b = *members_[j].initializer;
      const double rot =
          (a.currentPose().so3().inverse() * b.currentPose().so3()).log().norm() * kRadToDeg;
      const double dir =
          angleBetweenDeg(a.currentPose().translation(), b.currentPose().translation());
      if (rot > kSameRotationDeg || dir > kSameDirectionDeg) continue;
      // A second-chance hypothesis that found an existing one's motion adds nothing: the one
      // tracked since the reference stays (its depths have seen every frame).
      std::size_t worse = a.photometricEnergy() <= b.photometricEnergy() ? j : i;
      if (members_[i].restarted != members_[j].restarted) worse = members_[i].restarted ? i : j;
      members_[worse].alive = false;
      spdlog::trace("initializer hypothesis {} joins another one: dropped", worse);
    }
  }
}

void InitializerHypotheses::dropHopeless() {
  const int best = bestAlive();
  if (best < 0) return;
  const CoarseInitializer& b = *members_[static_cast<std::size_t>(best)].initializer;
  if (!seesParallax(b)) return;
  for (std::size_t i = 0; i < members_.size(); ++i) {
    const CoarseInitializer& h = *members_[i].initializer;
    // A second-chance hypothesis is held to the best one's fit from its first frame on: one
    // that never finds a basin would otherwise linger without parallax and keep the
    // initialisation from starting over when the others fail.
    if (!members_[i].alive || static_cast<int>(i) == best) continue;
    if (!seesParallax(h) && !members_[i].restarted) continue;
    // Where most points are outliers (capped) the energies of a fit and of garbage are close;
    // the inliers' RMS still tells them apart.
    if (members_[i].restarted &&
        h.lastFrameStats().rms_residual > kDropRmsRatio * b.lastFrameStats().rms_residual) {
      members_[i].alive = false;
      spdlog::trace("initializer hypothesis {}: rms {:.2f} against {:.2f}: dropped", i,
                    h.lastFrameStats().rms_residual, b.lastFrameStats().rms_residual);
      continue;
    }
    if (h.photometricEnergy() > kDropEnergyRatio * b.photometricEnergy()) {
      members_[i].alive = false;
      spdlog::trace("initializer hypothesis {}: energy {:.0f} against {:.0f}: dropped", i,
                    h.photometricEnergy(), b.photometricEnergy());
    }
  }
}

void InitializerHypotheses::restartDropped() {
  const CoarseInitializer& lead = *members_[static_cast<std::size_t>(leader_)].initializer;
  const double length = lead.currentPose().translation().norm();
  if (!(length > 0.0) || !std::isfinite(length)) return;
  for (std::size_t i = 1; i < members_.size(); ++i) {
    Member& m = members_[i];
    if (m.alive || m.restarted) continue;
    const Eigen::Vector3d start = seed(static_cast<int>(i)) * (length / kSeedLength);
    m.initializer->restartFrom(lead, SE3d(SO3d(), start));
    m.alive = true;
    m.restarted = true;
    spdlog::trace("initializer hypothesis {}: second chance from [{:.3f} {:.3f} {:.3f}]", i,
                  start.x(), start.y(), start.z());
  }
}

bool InitializerHypotheses::addFrame(const ImagePyramid& pyramid, double exposure, double timestamp,
                                     bool after_skipped) {
  const bool tracking = status_ == InitStatus::kWaitingForParallax ||
                        status_ == InitStatus::kConfirming || status_ == InitStatus::kComplete;
  if (!tracking) {
    startReference(pyramid, exposure);
    t_reference_ = t_last_ = timestamp;
    return false;
  }
  ++frames_;
  const double scale = (timestamp - t_reference_) / (t_last_ - t_reference_);
  t_last_ = timestamp;
  alive_scratch_.clear();
  for (std::size_t i = 0; i < members_.size(); ++i) {
    if (!members_[i].alive) continue;
    alive_scratch_.push_back(static_cast<int>(i));
    if (after_skipped && members_[i].initializer->continueMotion(scale))
      spdlog::trace("initializer frame {} hypothesis {}: motion continued x{:.2f}", frames_, i,
                    scale);
  }
  const auto track = [&](int k) {
    members_[static_cast<std::size_t>(alive_scratch_[static_cast<std::size_t>(k)])]
        .initializer->addFrame(pyramid, exposure);
  };
  const int live = static_cast<int>(alive_scratch_.size());
  concurrency::runTasks(tasks_, live, track);
  bool leader_failed = false;  // the hypothesis that led after the previous frame failed
  for (std::size_t i = 0; i < members_.size(); ++i) {
    Member& m = members_[i];
    if (!m.alive) continue;
    if (m.initializer->failed()) {
      m.alive = false;
      if (i == 0 || failure_ == InitFailure::kNone) failure_ = m.initializer->failure();
      leader_failed = leader_failed || static_cast<int>(i) == leader_;
    }
    if (spdlog::should_log(spdlog::level::trace)) {
      const CoarseInitializer& h = *m.initializer;
      const Eigen::Vector3d w = h.currentPose().so3().log() * kRadToDeg;
      const Eigen::Vector3d t = h.currentPose().translation().normalized();
      const InitFrameStats& s = h.lastFrameStats();
      spdlog::trace(
          "initializer frame {} hypothesis {}: {}, energy {:.0f}, flow {:.2f}, parallax {:.2f}, "
          "rms {:.2f}, {:.0f} % inliers, rotation [{:.3f} {:.3f} {:.3f}] deg, direction [{:.2f} "
          "{:.2f} {:.2f}]",
          frames_, i, toString(h.status()), h.photometricEnergy(), s.flow_translation, s.parallax,
          s.rms_residual, 100.0 * s.good_fraction, w.x(), w.y(), w.z(), t.x(), t.y(), t.z());
    }
  }
  dropDuplicates();
  dropHopeless();
  const int best = bestAlive();
  if (best < 0) {
    status_ = InitStatus::kFailed;
    if (failure_ == InitFailure::kNone) failure_ = InitFailure::kLostTrack;
    return false;
  }
  // The leader failed: the survivors fit the previous frame worse, they are in other basins
  // (started at frames 3 and 6 of the loop, the true motion's residual grew past the limit and a
  // hypothesis 27-30 degrees off would have completed). Start over from a new reference, as
  // after any failed initialisation.
  if (leader_failed && frames_ > 1) {
    const InitFailure why = members_[static_cast<std::size_t>(leader_)].initializer->failure();
    spdlog::debug("initializer: the leading hypothesis failed ({}); starting over", toString(why));
    status_ = InitStatus::kFailed;
    failure_ = why;
    return false;
  }
  leader_ = best;
  status_ = members_[static_cast<std::size_t>(best)].initializer->status();
  failure_ = InitFailure::kNone;
  if (second_chance_ && status_ == InitStatus::kConfirming) restartDropped();
  if (status_ == InitStatus::kComplete && leader_ != 0) {
    spdlog::debug("initializer: motion hypothesis {} (seed [{} {} {}]) wins", leader_,
                  seed(leader_).x(), seed(leader_).y(), seed(leader_).z());
  }
  return status_ == InitStatus::kComplete;
}

}  // namespace ldsm
