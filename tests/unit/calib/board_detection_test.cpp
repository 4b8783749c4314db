#include "ldsm/calib/board_detection.h"

#include <gtest/gtest.h>

#include <cmath>

#include "calibration_test_util.h"

namespace ldsm::calib {
namespace {

using drivers::sim::projectTargetCorners;

/// RMS distance between detected corners and the true ones (matched by grid position; a
/// chessboard may be found turned by 180 degrees, then matched reversed).
double cornerRms(const BoardSpec& spec, const BoardObservation& obs,
                 const std::vector<std::optional<Eigen::Vector2d>>& truth) {
  double best = 1e9;
  for (int turned = 0; turned < 2; ++turned) {
    double sum = 0;
    for (std::size_t k = 0; k < obs.grid.size(); ++k) {
      int ix = obs.grid[k].x(), iy = obs.grid[k].y();
      if (turned) ix = spec.innerCols() - 1 - ix, iy = spec.innerRows() - 1 - iy;
      const auto& t = truth[static_cast<std::size_t>(iy * spec.innerCols() + ix)];
      if (!t) return 1e9;
      sum += (*t - obs.image_points[k]).squaredNorm();
    }
    best = std::min(best, std::sqrt(sum / obs.grid.size()));
  }
  return best;
}

TEST(BoardDetection, ChessboardCornersMatchTheRenderedBoard) {
  const BoardSpec spec = test::boardSpec(BoardType::Chessboard);
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(test::radTanCamera());
  const auto poses = test::boardPoses(target, *camera, 4, 0.45);
  ASSERT_EQ(poses.size(), 4u);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const BoardView view = test::renderView(spec, target, *camera, poses[i], static_cast<int>(i));
    ASSERT_TRUE(view.observation) << "view " << i;
    const BoardObservation& obs = *view.observation;
    EXPECT_EQ(obs.image_points.size(), 40u);
    EXPECT_EQ(obs.width, test::kWidth);
    EXPECT_LT(cornerRms(spec, obs, projectTargetCorners(target, *camera, poses[i])), 0.15)
        << "view " << i;
    for (std::size_t k = 0; k < obs.grid.size(); ++k)
      EXPECT_EQ(obs.board_points[k], boardCorner(spec, obs.grid[k].x(), obs.grid[k].y()));
  }
}

TEST(BoardDetection, CharucoCornersMatchTheRenderedBoard) {
  const BoardSpec spec = test::boardSpec(BoardType::Charuco);
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(test::radTanCamera());
  const auto poses = test::boardPoses(target, *camera, 3, 0.45);
  ASSERT_EQ(poses.size(), 3u);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const BoardView view = test::renderView(spec, target, *camera, poses[i], static_cast<int>(i));
    ASSERT_TRUE(view.observation) << "view " << i;
    const BoardObservation& obs = *view.observation;
    EXPECT_GE(obs.image_points.size(), 18u);
    // ChArUco corners are identified: no turned match needed, the ids give the grid directly.
    const auto truth = projectTargetCorners(target, *camera, poses[i]);
    double sum = 0;
    for (std::size_t k = 0; k < obs.grid.size(); ++k)
      sum +=
          (*truth[static_cast<std::size_t>(obs.grid[k].y() * spec.innerCols() + obs.grid[k].x())] -
           obs.image_points[k])
              .squaredNorm();
    EXPECT_LT(std::sqrt(sum / obs.grid.size()), 0.15) << "view " << i;
  }
}

TEST(BoardDetection, EdgeBlurFollowsTheBlurOfTheImage) {
  const BoardSpec spec = test::boardSpec(BoardType::Chessboard);
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(test::pinholeCamera());
  const auto poses = test::boardPoses(target, *camera, 1, 0.4);
  ASSERT_EQ(poses.size(), 1u);
  double previous = 0;
  for (const double sigma : {0.0, 1.0, 2.0, 3.0}) {
    const BoardView view = test::renderView(spec, target, *camera, poses[0], 0, sigma);
    ASSERT_TRUE(view.observation) << "sigma " << sigma;
    const double blur = view.observation->blur_px;
    EXPECT_GT(blur, previous) << "sigma " << sigma;
    if (sigma == 0.0) {
      EXPECT_LT(blur, 0.9);
    } else {
      // The antialiasing and sampling add about 0.5 px in quadrature.
      EXPECT_NEAR(blur, std::sqrt(sigma * sigma + 0.25), 0.25 * sigma) << "sigma " << sigma;
    }
    previous = blur;
  }
}

TEST(BoardDetection, NoBoardInAPlainImage) {
  const BoardSpec spec = test::boardSpec(BoardType::Chessboard);
  ImageU8 grey(test::kWidth, test::kHeight, 128);
  EXPECT_FALSE(detectBoard(spec, grey.view()));
  EXPECT_FALSE(detectBoard(test::boardSpec(BoardType::Charuco), grey.view()));
  EXPECT_THROW(detectBoard(spec, ImageU8().view()), InputError);
}

TEST(BoardDetection, WrongSquareCountIsNotFound) {
  BoardSpec spec = test::boardSpec(BoardType::Chessboard);
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(test::pinholeCamera());
  const auto poses = test::boardPoses(target, *camera, 1, 0.4);
  ASSERT_EQ(poses.size(), 1u);
  spec.cols = 10;  // inner corners given as squares + 1: a common mistake
  EXPECT_FALSE(test::renderView(spec, target, *camera, poses[0], 0).observation);
}

TEST(BoardDetection, DrawnChessboardHasItsSquaresWhereTheSpecSays) {
  const BoardSpec spec = test::boardSpec(BoardType::Chessboard);
  const ImageU8 img = drawBoard(spec, 10, 5);
  ASSERT_EQ(img.width(), 9 * 10 + 10);
  ASSERT_EQ(img.height(), 6 * 10 + 10);
  EXPECT_EQ(img(2, 2), 255);  // margin
  EXPECT_EQ(img(5, 5), 0);    // first square black
  EXPECT_EQ(img(14, 14), 0);
  EXPECT_EQ(img(15, 5), 255);  // second square white
  EXPECT_EQ(img(15, 15), 0);   // diagonal neighbour black
  const ImageU8 charuco = drawBoard(test::boardSpec(BoardType::Charuco), 20, 10);
  EXPECT_EQ(charuco.width(), 7 * 20 + 20);
  EXPECT_EQ(charuco(15, 15), 0);  // first square black, as for the chessboard
}

TEST(BoardDetection, InvalidSpecsNameTheOption) {
  auto expectConfig = [](const BoardSpec& spec, const std::string& text) {
    try {
      validateBoardSpec(spec);
      ADD_FAILURE() << "no error, expected '" << text << "'";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  BoardSpec s = test::boardSpec(BoardType::Chessboard);
  s.cols = 2;
  expectConfig(s, "--cols");
  s = test::boardSpec(BoardType::Chessboard);
  s.square_m = 0;
  expectConfig(s, "--square");
  s = test::boardSpec(BoardType::Charuco);
  s.marker_m = s.square_m;
  expectConfig(s, "--marker");
  s = test::boardSpec(BoardType::Charuco);
  s.dictionary = "DICT_9X9_1";
  expectConfig(s, "--dictionary");
  s = test::boardSpec(BoardType::Charuco);
  s.cols = 12;
  s.rows = 10;  // 60 markers, DICT_4X4_50 has 50
  expectConfig(s, "needs 60");
  EXPECT_EQ(parseBoardType("ChArUco"), BoardType::Charuco);
  EXPECT_THROW(parseBoardType("aprilgrid"), ConfigError);
}

}  // namespace
}  // namespace ldsm::calib
