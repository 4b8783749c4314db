#include "ldsm/drivers/sim/photometric_sequences.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <system_error>

#include "ldsm/calib/image_file.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/drivers/sim/image_formation.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace fs = std::filesystem;
namespace {

std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

ExposedFrames form(const ImageFormation& formation, const ImageF& irradiance,
                   const std::vector<double>& reported, const std::vector<double>& formed,
                   std::uint32_t seed) {
  ExposedFrames out;
  out.truth.has_response = true;
  out.truth.inverse_response = formation.inverseResponse();
  out.truth.vignette = formation.vignette();
  out.exposures_ms = reported;
  out.images.resize(reported.size());
  for (std::size_t i = 0; i < reported.size(); ++i)
    formation.apply(irradiance, formed[i], hash32(seed, static_cast<std::uint32_t>(i)),
                    out.images[i]);
  return out;
}

}  // namespace

std::vector<double> exposureSweepTimes(double min_ms, double max_ms, int count) {
  if (!(min_ms > 0 && max_ms > min_ms && std::isfinite(max_ms)) || count < 2)
    throw ConfigError("exposure sweep: need 0 < min < max and at least 2 exposures");
  std::vector<double> t;
  const double ratio = detLog(max_ms / min_ms);
  for (int i = 0; i < count; ++i) t.push_back(min_ms * detExp(ratio * i / (count - 1)));
  t.back() = max_ms;
  return t;
}

ExposedFrames renderExposureSweep(const std::string& scene, const SimOptions& options,
                                  const std::vector<double>& exposures_ms,
                                  const std::vector<double>& formed_exposures_ms) {
  if (!formed_exposures_ms.empty() && formed_exposures_ms.size() != exposures_ms.size())
    throw ConfigError("exposure sweep: formed exposures must match the reported ones in count");
  SimOptions o = options;
  o.frames = 1;
  o.exposure_changes = false;
  SimSource source(scene, o);
  ImageF irradiance;
  source.renderer().renderIrradiance(source.groundTruth().front().pose, irradiance);
  return form(source.imageFormation(), irradiance, exposures_ms,
              formed_exposures_ms.empty() ? exposures_ms : formed_exposures_ms, o.seed);
}

ExposedFrames renderFlatField(const SimOptions& options, double irradiance,
                              const std::vector<double>& exposures_ms, double spot) {
  validate(options);
  if (!(irradiance > 0) || !(spot >= 0 && spot < 1))
    throw ConfigError("flat field: irradiance must be positive and spot in [0, 1)");
  const PinholeIntrinsics camera = simIntrinsics(options);
  const ImageFormation formation(options, camera);
  ImageF flat(camera.width, camera.height, static_cast<float>(irradiance));
  if (spot > 0) {
    const double r = camera.height / 8.0, cx = camera.width / 4.0, cy = camera.height / 4.0;
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x)
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r)
          flat(x, y) = static_cast<float>(irradiance * (1.0 - spot));
  }
  return form(formation, flat, exposures_ms, exposures_ms, options.seed + 7919u);
}

void writeExposedFrames(const std::string& out_dir, const std::vector<ImageU8>& images,
                        const std::vector<double>& exposures_ms) {
  if (images.size() != exposures_ms.size())
    throw ConfigError("exposed frames: as many exposure times as images needed");
  const fs::path root(out_dir);
  std::error_code ec;
  fs::create_directories(root / "images", ec);
  if (!fs::is_directory(root / "images"))
    throw Error((root / "images").string() + ": cannot create directory");
  std::string times;
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::string name = std::to_string(i);
    name.insert(0, name.size() < 5 ? 5 - name.size() : 0, '0');
    calib::writePng((root / "images" / (name + ".png")).string(), images[i].view());
    times += name + ' ' + shortest(0.1 * static_cast<double>(i)) + ' ' + shortest(exposures_ms[i]) +
             '\n';
  }
  writeFileAtomically((root / "times.txt").string(), times);
}

}  // namespace ldsm::drivers::sim
