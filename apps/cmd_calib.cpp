// `ldsm calib`: calibrating a camera with ldsm alone.
//   ldsm calib camera   --images DIR|--device /dev/videoN --board chessboard|charuco --cols N
//                       --rows N --square M [--marker M] [--dictionary D]
//                       --model pinhole|radtan|equidistant --out DIR
//   ldsm calib response --sweep DIR|--device /dev/videoN --out DIR [--reference pcalib.txt]
//   ldsm calib vignette --images DIR|--device /dev/videoN --pcalib FILE --out DIR
//   ldsm calib board    --board ... --out board.png      (a board image to print)
//   ldsm calib synth    --kind board|sweep|flat --out DIR (synthetic data to try the tools on)
// Each writes its files and plots into --out, a summary on stdout and warnings on stderr.
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "calib_device.h"
#include "calib_reports.h"
#include "calib_synth.h"
#include "calibration_plots.h"
#include "commands.h"
#include "ldsm/calib/camera_calibration.h"
#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/image_file.h"
#include "ldsm/calib/kalibr_yaml.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/calib/response_calibration.h"
#include "ldsm/calib/vignette_calibration.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/error.h"

namespace ldsm::app {
namespace {

namespace fs = std::filesystem;

struct BoardOptions {
  std::string type = "chessboard";
  int cols = 0, rows = 0;
  double square = 0, marker = 0;
  std::string dictionary = "DICT_5X5_100";

  calib::BoardSpec spec() const {
    calib::BoardSpec s;
    s.type = calib::parseBoardType(type);
    s.cols = cols;
    s.rows = rows;
    s.square_m = square;
    s.marker_m = marker;
    s.dictionary = dictionary;
    calib::validateBoardSpec(s);
    return s;
  }
};

struct CameraCommand {
  std::string images, model = "radtan", out;
  BoardOptions board;
  calib::CameraCalibrationOptions calibration;
  DeviceOptions device;
  int views = 20;
  std::int64_t max_frames = 3000;
};

struct ResponseCommand {
  std::string sweep, out, reference;
  calib::ResponseCalibrationOptions calibration;
  DeviceOptions device;
  double exposure_min = 0.1, exposure_max = 100.0;
  int steps = 30, settle = 4;
};

struct VignetteCommand {
  std::string images, pcalib, out;
  std::vector<double> centre;
  DeviceOptions device;
  double exposure = 0.0;
  int frames = 20, every = 15;
};

/// Exactly one of a folder and a camera.
void requireOneInput(const std::string& folder, const char* folder_option,
                     const DeviceOptions& device) {
  if (folder.empty() == device.device.empty())
    throw ConfigError(std::string("calib: give either ") + folder_option +
                      " (recorded images) or --device (a camera)");
}

struct BoardCommand {
  BoardOptions board;
  int px_per_square = 100;
  std::string out;
};

CameraModelType parseModel(const std::string& name) {
  if (name == "pinhole") return CameraModelType::Pinhole;
  if (name == "radtan") return CameraModelType::RadTan;
  if (name == "equidistant") return CameraModelType::Equidistant;
  throw ConfigError("--model '" + name + "' is not pinhole, radtan or equidistant");
}

void require(const std::string& value, const char* what) {
  if (value.empty()) throw ConfigError(std::string("calib: ") + what + " is required");
}

fs::path outputDir(const std::string& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!fs::is_directory(out)) throw Error(out + ": cannot create the output folder");
  return fs::path(out);
}

std::string fileName(const std::string& path) {
  return fs::path(path).filename().string();
}

/// The frames of a dataset folder with their exposure times (NaN when not given) and names.
struct LoadedImages {
  std::vector<ImageU8> images;
  std::vector<double> exposures_ms;
  std::vector<std::string> names;

  std::vector<calib::ExposedImage> exposed(double unknown_exposure) const {
    std::vector<calib::ExposedImage> in;
    for (std::size_t i = 0; i < images.size(); ++i)
      in.push_back({images[i].view(),
                    std::isnan(exposures_ms[i]) ? unknown_exposure : exposures_ms[i], names[i]});
    return in;
  }
};

LoadedImages loadImages(const drivers::DatasetDescription& desc) {
  LoadedImages out;
  auto source = drivers::openDataset(desc);
  drivers::Frame frame;
  while (source->next(frame)) {
    const std::size_t i = out.images.size();
    out.images.push_back(frame.image);
    out.exposures_ms.push_back(frame.exposure_ms);
    out.names.push_back(i < desc.images.size() ? fileName(desc.images[i])
                                               : "frame " + std::to_string(i));
  }
  return out;
}

// ---- camera ----------------------------------------------------------------------------------

/// The board views of a folder of images.
std::vector<calib::BoardView> detectInFolder(const std::string& dir, const calib::BoardSpec& spec,
                                             int& width, int& height) {
  const auto desc = drivers::describeDataset(dir, drivers::DatasetFormat::Folder);
  width = desc.width;
  height = desc.height;
  std::vector<calib::BoardView> views;
  ImageU8 image;
  for (const std::string& path : desc.images) {
    calib::readImage(path, image);
    if (image.width() != desc.width || image.height() != desc.height)
      throw InputError(path + ": image is " + std::to_string(image.width()) + "x" +
                       std::to_string(image.height()) + " but the first one is " +
                       std::to_string(desc.width) + "x" + std::to_string(desc.height));
    views.push_back({fileName(path), calib::detectBoard(spec, image.view())});
    spdlog::info("{}: {}", path, views.back().observation ? "board found" : "no board");
  }
  return views;
}

int runCamera(const CameraCommand& o) {
  requireOneInput(o.images, "--images", o.device);
  require(o.out, "--out");
  const calib::BoardSpec spec = o.board.spec();
  calib::CameraCalibrationOptions options = o.calibration;
  options.model = parseModel(o.model);
  int width = 0, height = 0;
  const fs::path out = outputDir(o.out);
  const std::vector<calib::BoardView> views =
      o.images.empty() ? captureBoardFromDevice(o.device, spec, o.views, o.max_frames,
                                                (out / "images").string(), width, height)
                       : detectInFolder(o.images, spec, width, height);
  const std::string source = o.images.empty() ? o.device.device : o.images;
  const auto r = calib::calibrateCamera(views, width, height, options, source);

  calib::writeDsoCameraFile((out / "camera.txt").string(), r.calibration);
  calib::writeKalibrCameraYaml((out / "camchain.yaml").string(), r.calibration);
  drivers::writeFileAtomically((out / "calibration_report.txt").string(),
                               cameraReportText(source, spec, o.model, r));
  writeCoveragePlot((out / "coverage.png").string(), r, width, height);
  printCameraSummary(r,
                     std::string("camera.txt camchain.yaml calibration_report.txt coverage.png") +
                         (o.images.empty() ? " images/" : "") + " in " + o.out);
  return 0;
}

// ---- response --------------------------------------------------------------------------------

LoadedImages fromCapture(drivers::CapturedImages&& c) {
  LoadedImages out;
  out.images = std::move(c.images);
  out.exposures_ms = std::move(c.exposures_ms);
  for (std::size_t i = 0; i < out.images.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%05zu.png", i);
    out.names.emplace_back(name);
  }
  return out;
}

int runResponse(const ResponseCommand& o) {
  requireOneInput(o.sweep, "--sweep", o.device);
  require(o.out, "--out");
  const fs::path out = outputDir(o.out);
  LoadedImages loaded;
  std::string source = o.sweep;
  if (o.sweep.empty()) {
    source = (out / "sweep").string();
    loaded = fromCapture(captureSweepFromDevice(o.device, o.exposure_min, o.exposure_max, o.steps,
                                                o.settle, source));
  } else {
    const auto desc = drivers::describeDataset(o.sweep, drivers::DatasetFormat::TumMono);
    if (!desc.hasExposures())
      throw InputError(desc.timestamps_file +
                       ": no exposure times; each line must be 'id timestamp exposure_ms'");
    loaded = loadImages(desc);
  }
  const auto r = calib::calibrateResponse(loaded.exposed(std::nan("")), o.calibration, source);
  std::array<float, 256> reference{};
  if (!o.reference.empty()) reference = calib::readInverseResponse(o.reference);

  calib::writeInverseResponse((out / "pcalib.txt").string(), r.inverse_response);
  writeResponsePlot((out / "response.png").string(), r, o.reference.empty() ? nullptr : &reference);

  printResponseSummary(r, loaded.images.size(), o.reference.empty() ? nullptr : &reference,
                       "pcalib.txt response.png in " + o.out);
  return 0;
}

// ---- vignette --------------------------------------------------------------------------------

int runVignette(const VignetteCommand& o) {
  requireOneInput(o.images, "--images", o.device);
  require(o.pcalib, "--pcalib (the inverse response, e.g. from ldsm calib response)");
  require(o.out, "--out");
  if (!o.centre.empty() && o.centre.size() != 2)
    throw ConfigError("calib vignette: --centre takes two numbers, x and y in pixels");
  const auto g = calib::readInverseResponse(o.pcalib);
  const fs::path out = outputDir(o.out);
  LoadedImages loaded;
  std::string source = o.images;
  if (o.images.empty()) {
    source = (out / "flat").string();
    loaded = fromCapture(captureFlatFromDevice(o.device, o.exposure, o.frames, o.every, source));
  } else {
    loaded = loadImages(drivers::describeDataset(o.images));
  }
  // Each image is normalised by its median, so unknown exposure times do not matter.
  calib::VignetteCalibrationOptions options;
  if (o.centre.size() == 2) options.centre = Eigen::Vector2d(o.centre[0], o.centre[1]);
  const auto r = calib::calibrateVignette(loaded.exposed(1.0), g, options, source);

  calib::writeVignette((out / "vignette.png").string(), r.vignette);
  writeVignettePlot((out / "vignette_plot.png").string(), r);
  printVignetteSummary(r, loaded.images.size(), "vignette.png vignette_plot.png in " + o.out);
  return 0;
}

// ---- board image -----------------------------------------------------------------------------

int runBoard(const BoardCommand& o) {
  require(o.out, "--out (the PNG file to write)");
  const calib::BoardSpec spec = o.board.spec();
  const ImageU8 img = calib::drawBoard(spec, o.px_per_square, o.px_per_square / 2);
  calib::writePng(o.out, img.view());
  std::printf("board:        %s %dx%d squares, %dx%d pixels (%d per square)\n",
              calib::toString(spec.type), spec.cols, spec.rows, img.width(), img.height(),
              o.px_per_square);
  std::printf("print so that a square measures %.1f mm (or measure it and pass --square)\n",
              1000 * spec.square_m);
  return 0;
}

// ---- options ---------------------------------------------------------------------------------

void addDeviceOptions(CLI::App* sub, DeviceOptions& d) {
  sub->add_option("--device", d.device, "Capture with this V4L2 camera instead (e.g. /dev/video0)");
  sub->add_option("--width", d.width, "--device: image width (0: the largest)");
  sub->add_option("--height", d.height, "--device: image height (0: the largest)");
  sub->add_option("--gain", d.gain, "--device: fixed gain in the camera's units (auto-gain off)");
}

void addBoardOptions(CLI::App* sub, BoardOptions& b) {
  sub->add_option("--board", b.type, "Board type: chessboard or charuco")->capture_default_str();
  sub->add_option("--cols", b.cols, "Squares along the board's width (not inner corners)");
  sub->add_option("--rows", b.rows, "Squares along the board's height (not inner corners)");
  sub->add_option("--square", b.square, "Side of a square in metres");
  sub->add_option("--marker", b.marker, "ChArUco: side of a marker in metres");
  sub->add_option("--dictionary", b.dictionary, "ChArUco: ArUco dictionary, e.g. DICT_5X5_100")
      ->capture_default_str();
}

}  // namespace

void addCalibCommand(CLI::App& app, CommandResult& result) {
  CLI::App* calib = app.add_subcommand(
      "calib", "Calibrate a camera: intrinsics from a board, response and vignette");
  calib->require_subcommand(1);

  auto cam = std::make_shared<CameraCommand>();
  CLI::App* c = calib->add_subcommand(
      "camera",
      "Intrinsics from pictures of a chessboard or ChArUco board: camera.txt, "
      "camchain.yaml, a per-view report and a coverage plot");
  c->add_option("--images", cam->images, "Folder of board pictures");
  addBoardOptions(c, cam->board);
  c->add_option("--model", cam->model, "pinhole, radtan or equidistant")
      ->check(CLI::IsMember({"pinhole", "radtan", "equidistant"}))
      ->capture_default_str();
  c->add_option("--out", cam->out, "Output folder (created)");
  c->add_option("--min-views", cam->calibration.min_views, "Fewest usable views accepted")
      ->capture_default_str();
  addDeviceOptions(c, cam->device);
  c->add_option("--views", cam->views, "--device: views to capture")->capture_default_str();
  c->add_option("--max-frames", cam->max_frames, "--device: give up after this many frames")
      ->capture_default_str();
  c->callback([cam, &result]() { result.exit_code = runCamera(*cam); });

  auto resp = std::make_shared<ResponseCommand>();
  CLI::App* r = calib->add_subcommand(
      "response", "Inverse response G^-1 (pcalib.txt) from an exposure sweep of a static scene");
  r->add_option("--sweep", resp->sweep, "TUM-Mono style folder: images/ + times.txt (id t ms)");
  r->add_option("--out", resp->out, "Output folder (created)");
  r->add_option("--reference", resp->reference, "A known pcalib.txt to compare with and plot");
  r->add_flag("--force", resp->calibration.allow_inconsistent,
              "Write a result even when brightness does not follow exposure (auto-gain?)");
  r->add_option("--min-value", resp->calibration.min_value, "Darker pixel values are not used")
      ->capture_default_str();
  r->add_option("--max-value", resp->calibration.max_value,
                "Brighter pixel values count as saturated")
      ->capture_default_str();
  addDeviceOptions(r, resp->device);
  r->add_option("--exposure-min", resp->exposure_min, "--device: shortest exposure (ms)")
      ->capture_default_str();
  r->add_option("--exposure-max", resp->exposure_max, "--device: longest exposure (ms)")
      ->capture_default_str();
  r->add_option("--steps", resp->steps, "--device: number of exposures")->capture_default_str();
  r->add_option("--settle", resp->settle, "--device: frames dropped after each change")
      ->capture_default_str();
  r->callback([resp, &result]() { result.exit_code = runResponse(*resp); });

  auto vig = std::make_shared<VignetteCommand>();
  CLI::App* v = calib->add_subcommand(
      "vignette", "Vignette (vignette.png) from pictures of a flat, evenly lit surface");
  v->add_option("--images", vig->images,
                "Folder of pictures (TUM-Mono style with times.txt, or plain images)");
  v->add_option("--pcalib", vig->pcalib, "Inverse response pcalib.txt");
  v->add_option("--out", vig->out, "Output folder (created)");
  v->add_option("--centre", vig->centre, "Vignette centre x y in pixels (default: fitted)")
      ->expected(2);
  addDeviceOptions(v, vig->device);
  v->add_option("--exposure", vig->exposure,
                "--device: exposure in ms (0: auto-exposure, locked at its first value)")
      ->capture_default_str();
  v->add_option("--frames", vig->frames, "--device: images to take")->capture_default_str();
  v->add_option("--every", vig->every, "--device: frames between two images")
      ->capture_default_str();
  v->callback([vig, &result]() { result.exit_code = runVignette(*vig); });

  auto board = std::make_shared<BoardCommand>();
  CLI::App* b = calib->add_subcommand("board", "Write a board image to print");
  addBoardOptions(b, board->board);
  b->add_option("--px-per-square", board->px_per_square, "Pixels per square")
      ->capture_default_str();
  b->add_option("--out", board->out, "PNG file to write");
  b->callback([board, &result]() { result.exit_code = runBoard(*board); });

  auto synth = std::make_shared<CalibSynthOptions>();
  auto synth_board = std::make_shared<BoardOptions>();
  auto synth_model = std::make_shared<std::string>("radtan");
  auto synth_response = std::make_shared<std::string>("gamma");
  synth_board->cols = 9;
  synth_board->rows = 6;
  synth_board->square = 0.03;
  synth_board->marker = 0.022;
  CLI::App* s = calib->add_subcommand(
      "synth", "Render synthetic input for the tools with a known camera, response and vignette");
  s->add_option("--kind", synth->kind, "board, sweep or flat")
      ->check(CLI::IsMember({"board", "sweep", "flat"}));
  s->add_option("--out", synth->out, "Output folder (created)");
  addBoardOptions(s, *synth_board);
  s->add_option("--model", *synth_model, "board: camera model (pinhole, radtan, equidistant)")
      ->capture_default_str();
  s->add_option("--views", synth->views, "board: number of distinct views")->capture_default_str();
  s->add_option("--blurred", synth->blurred, "board: extra blurred views")->capture_default_str();
  s->add_option("--duplicates", synth->duplicates, "board: extra near-duplicate views")
      ->capture_default_str();
  s->add_flag("--auto-gain", synth->auto_gain, "sweep: a camera with auto-gain left on");
  s->add_option("--width", synth->render.width, "Image width")->capture_default_str();
  s->add_option("--height", synth->render.height, "Image height")->capture_default_str();
  s->add_option("--response", *synth_response, "linear, gamma or scurve")->capture_default_str();
  s->add_option("--vignette", synth->render.vignette, "Vignette strength: 1 - V at the corners")
      ->capture_default_str();
  s->add_option("--noise", synth->render.noise_sigma, "Noise sigma (grey levels)")
      ->capture_default_str();
  s->callback([synth, synth_board, synth_model, synth_response, &result]() {
    synth->board = synth_board->spec();
    synth->model = parseModel(*synth_model);
    synth->render.response = drivers::sim::parseSimResponse(*synth_response);
    runCalibSynth(*synth);
    result.exit_code = 0;
  });
}

}  // namespace ldsm::app
