// Monocular initialisation from several motion hypotheses.
//
// Over the first few centimetres of motion a yaw (or pitch) and a sideways (or vertical)
// translation move the image almost alike, and the coarse initializer's estimate settles in the
// basin of its starting guess: in a corridor, starting at rest, it can pick a translation 30
// degrees off and a rotation of the wrong sign, whose wrong depths then fit every later frame
// well enough to stay (the bundle adjustment cannot leave that basin either). The photometric
// error does tell the basins apart once the parallax is real (RMS 3.5 against 5.1 grey levels on
// the synthetic loop corridor), so this class runs one CoarseInitializer per starting guess on
// the same reference points: at rest and with a small translation along +-x, +-y and +-z of the
// camera. Every frame goes to every hypothesis still alive. Hypotheses that fail, or that
// converged to the same motion as a better one, are dropped, and those far worse than the best
// once both have real parallax. The initialisation completes when the hypothesis with the lowest
// photometric energy over the reference points is complete.
//
// Second chance: over the first frame's parallax of a few pixels the basins are close, and every
// seed can fall into the wrong ones (measured on the corridor loop started 3 frames later: all
// seven hypotheses in two wrong basins after the first frame, the initialisation 4.9 grey levels
// RMS instead of 3.5, and the whole run lost, ATE 0.45 m). So when the leading hypothesis sees
// real parallax (confirming), each seeded hypothesis that was dropped or failed starts once more
// on the same reference, from its seed's direction at the leader's translation length: seeds at
// the real parallax tell the basins apart. A second-chance hypothesis is dropped as soon as its
// energy is far worse than the best one's (it need not see parallax first: one that never finds
// a basin must not linger), and when it converges onto an original hypothesis' motion it is the
// one dropped. When the hypothesis that led after the previous frame fails, the survivors fit
// that frame worse: the initialisation starts over from a new reference, as with one hypothesis.
//
// Costs: one initializer's time per live hypothesis for the few frames of the initialisation.
// Memory: the hypotheses share the reference selection (only the first owns a PixelSelector).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <vector>

#include "concurrency/parallel_tasks.h"
#include "frontend/coarse_initializer.h"

namespace ldsm {

class InitializerHypotheses {
 public:
  /// Largest number of hypotheses (rest, +-x, +-y, +-z).
  static constexpr int kMaxHypotheses = 7;
  /// Length of the seed translations, in units of the mean inverse depth: about 3 % of the mean
  /// depth, a few frames' motion at 30 Hz in a room, so that a seed is not washed out by the
  /// first frame's tiny parallax (measured on the corridor start: 0.01 let the -x seed fall into
  /// the wrong basin with the others; 0.03 keeps one hypothesis in the right one).
  static constexpr double kSeedLength = 0.03;
  /// A hypothesis whose photometric energy exceeds the best one's by this factor, once both see
  /// real parallax (confirming or complete), is dropped.
  static constexpr double kDropEnergyRatio = 1.3;
  /// A second-chance hypothesis whose inliers' RMS residual exceeds the best one's by this
  /// factor is dropped (on the rendered rotation scene second-chance hypotheses at 12 grey levels
  /// against the leader's 2.8 had energies within 5 % of it: most points were capped outliers).
  static constexpr double kDropRmsRatio = 1.5;
  /// The leading hypothesis has the lowest photometric energy, unless one with at least
  /// kComparableInliers of the most inliers any hypothesis has fits its inliers with less than
  /// kClearlyBetterRms times that one's RMS residual (then the lowest such RMS leads). On the
  /// corridor loop the true motion had 0.63-0.75 times the RMS of a wrong one with less energy;
  /// while panning (rotation scene) the hypotheses' RMS differ by less than 10 %.
  static constexpr double kComparableInliers = 0.9;
  static constexpr double kClearlyBetterRms = 0.8;
  /// Another hypothesis takes the lead by energy only below this times the leader's energy.
  static constexpr double kTakeOverEnergy = 0.97;
  /// Two hypotheses closer than this in rotation (degrees) and translation direction (degrees)
  /// are the same: the one with the higher energy is dropped.
  static constexpr double kSameRotationDeg = 0.05;
  static constexpr double kSameDirectionDeg = 1.0;

  /// `hypotheses` in [1, kMaxHypotheses]: 1 is the plain initializer starting at rest. Throws
  /// ConfigError on invalid settings or count, InputError on an invalid camera.
  InitializerHypotheses(const PyramidCamera& camera, const CoarseInitializerSettings& settings,
                        int hypotheses);

  /// Same contract as CoarseInitializer::addFrame(): the first frame (after a failure or reset())
  /// becomes the reference; returns true when the initialisation is complete. `timestamp`
  /// (seconds) is when the frame was taken; `after_skipped`: frames came since the previous one
  /// given here that this initializer did not see (live mode, it was busy with that one). Then
  /// the confirming hypotheses continue their motion for the time that passed
  /// (CoarseInitializer::continueMotion()): from its last estimate alone, a frame three frames of
  /// a car's motion on was fitted at 10 grey levels RMS and the initialisation went astray.
  bool addFrame(const ImagePyramid& pyramid, double exposure,
                double timestamp = std::numeric_limits<double>::quiet_NaN(),
                bool after_skipped = false);
  void reset();
  /// reset() and give back every hypothesis' memory, the primary's point selector included
  /// (about 10 MB at 1232x368); it is allocated again with the next reference. For after a
  /// successful initialisation, when the map needs the memory more.
  void releaseMemory();

  /// Status of the leading (lowest-energy) hypothesis; kFailed when all of them failed.
  InitStatus status() const { return status_; }
  InitFailure failure() const { return failure_; }
  bool failed() const { return status_ == InitStatus::kFailed; }
  bool complete() const { return status_ == InitStatus::kComplete; }
  int framesTracked() const { return frames_; }
  /// Diagnostics of the leading hypothesis.
  const InitFrameStats& lastFrameStats() const;
  /// The chosen hypothesis' result; valid once addFrame() returned true.
  const InitializationResult& result() const;
  /// Index of the leading hypothesis (0: started at rest) and how many are still alive.
  int leader() const { return leader_; }
  int alive() const;
  int hypotheses() const { return static_cast<int>(members_.size()); }
  /// From now on the hypotheses of a frame are tracked as parallel tasks on `tasks` (not owned;
  /// null: one after the other). Each hypothesis only touches its own state and the results are
  /// combined in hypothesis order, so they are the same either way.
  void setParallelTasks(concurrency::ParallelTasks* tasks) { tasks_ = tasks; }
  /// The second chance (see the top; on by default). Off: dropped seeds stay dropped.
  void setSecondChance(bool on) { second_chance_ = on; }
  /// Seed translation of hypothesis i.
  static Eigen::Vector3d seed(int i);

 private:
  struct Member {
    std::unique_ptr<CoarseInitializer> initializer;
    bool alive = false;
    bool restarted = false;  ///< had its second chance on this reference
  };
  void startReference(const ImagePyramid& pyramid, double exposure);
  void dropDuplicates();
  void dropHopeless();
  int bestAlive() const;
  /// The second chance (see the top): restarts the dead seeded hypotheses from the leader.
  void restartDropped();

  std::vector<Member> members_;
  InitStatus status_ = InitStatus::kNoReference;
  InitFailure failure_ = InitFailure::kNone;
  int frames_ = 0;
  int leader_ = 0;
  concurrency::ParallelTasks* tasks_ = nullptr;
  bool second_chance_ = true;
  double t_reference_ = std::numeric_limits<double>::quiet_NaN();  ///< the reference's time
  double t_last_ = std::numeric_limits<double>::quiet_NaN();       ///< the last frame's time
  std::vector<int> alive_scratch_;  ///< indices of the live hypotheses of the frame
};

}  // namespace ldsm
