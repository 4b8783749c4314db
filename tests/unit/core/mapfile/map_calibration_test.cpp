#include "mapfile/map_calibration.h"

#include <gtest/gtest.h>

namespace ldsm {
namespace {

MapCalibration euroc() {
  PhotometricCalibration photometric;
  photometric.has_response = true;
  for (int i = 0; i < 256; ++i) photometric.inverse_response[static_cast<std::size_t>(i)] = 1.5f * i;
  return makeMapCalibration(PinholeIntrinsics{458.654, 457.296, 367.215, 248.375, 752, 480},
                            -0.01, photometric);
}

TEST(MapCalibration, TheSameCameraMatches) {
  const MapCalibration a = euroc();
  EXPECT_EQ(mapCalibrationMismatch(a, a), "");
  MapCalibration b = a;
  b.camera.fx *= 1.0 + 2e-6;  // within the tolerance
  b.radial_k = 0.2;           // an estimate of the run, not compared
  EXPECT_EQ(mapCalibrationMismatch(a, b), "");
}

TEST(MapCalibration, MessagesNameTheFieldAndBothValues) {
  const MapCalibration a = euroc();
  MapCalibration b = a;
  b.camera.width = 640;
  EXPECT_EQ(mapCalibrationMismatch(a, b), "image size 752x480 in the map, 640x480 now");
  b = a;
  b.camera.fx = 460.0;
  EXPECT_EQ(mapCalibrationMismatch(a, b), "fx 458.654 in the map, 460 now");
  b = a;
  b.camera.cy = 250.0;
  EXPECT_EQ(mapCalibrationMismatch(a, b), "cy 248.375 in the map, 250 now");
  b = a;
  b.camera.fy = 457.31;
  EXPECT_EQ(mapCalibrationMismatch(a, b), "fy 457.296 in the map, 457.31 now");
  b = a;
  b.camera.cx = 0.0;
  EXPECT_EQ(mapCalibrationMismatch(a, b), "cx 367.215 in the map, 0 now");
}

TEST(MapCalibration, APhotometricChangeIsReported) {
  const MapCalibration a = euroc();
  MapCalibration b = makeMapCalibration(a.camera, a.radial_k, PhotometricCalibration{});
  EXPECT_EQ(b.photometric_hash, 0u);
  const std::string m = mapCalibrationMismatch(a, b);
  EXPECT_EQ(m.rfind("photometric calibration response only, hash ", 0), 0u) << m;
  EXPECT_NE(m.find(" in the map, none, hash 0000000000000000 now"), std::string::npos) << m;
}

TEST(MapCalibration, ThePhotometricHashSeesEveryValue) {
  PhotometricCalibration p;
  EXPECT_EQ(photometricHash(p), 0u);
  p.has_response = true;
  const std::uint64_t response_only = photometricHash(p);
  EXPECT_NE(response_only, 0u);
  p.inverse_response[200] = 1e-3f;
  EXPECT_NE(photometricHash(p), response_only);
  p.vignette = ImageF(4, 3, 0.5f);
  const std::uint64_t with_vignette = photometricHash(p);
  EXPECT_NE(with_vignette, response_only);
  p.vignette(3, 2) = 0.25f;
  EXPECT_NE(photometricHash(p), with_vignette);
  PhotometricCalibration q;
  q.vignette = ImageF(3, 4, 0.5f);  // same values, other shape
  PhotometricCalibration r;
  r.vignette = ImageF(4, 3, 0.5f);
  EXPECT_NE(photometricHash(q), photometricHash(r));
  const MapCalibration c = makeMapCalibration(PinholeIntrinsics{}, 0.0, p);
  EXPECT_TRUE(c.has_response);
  EXPECT_TRUE(c.has_vignette);
  EXPECT_EQ(c.photometric_hash, photometricHash(p));
}

}  // namespace
}  // namespace ldsm
