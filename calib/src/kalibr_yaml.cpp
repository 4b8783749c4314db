#include "ldsm/calib/kalibr_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <sstream>
#include <utility>
#include <vector>

#include "ldsm/camera/camera_model.h"
#include "ldsm/error.h"
#include "text_file.h"

namespace ldsm::calib {
namespace {

/// 1-based line of a node, or `fallback` for nodes without a position (missing keys).
int lineOf(const YAML::Node& node, int fallback) {
  if (!node) return fallback;  // Mark() throws on missing nodes
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? mark.line + 1 : fallback;
}

/// OpenCV writes "%YAML:1.0", which yaml-cpp rejects: comment such lines out (keeps numbering).
std::string withoutOpenCvDirective(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.rfind("%YAML:", 0) == 0) line = "#" + line;
    out += line;
    out += '\n';
  }
  return out;
}

class CameraNode {
 public:
  CameraNode(YAML::Node node, std::string name) : node_(std::move(node)), name_(std::move(name)) {}

  int line() const { return lineOf(node_, 1); }

  YAML::Node required(const std::string& key) const {
    const YAML::Node n = std::as_const(node_)[key];
    if (!n) throw InputError(atLine(name_, line(), "missing key '" + key + "'"));
    return n;
  }

  std::string scalar(const std::string& key) const {
    const YAML::Node n = required(key);
    if (!n.IsScalar())
      throw InputError(atLine(name_, lineOf(n, line()), "'" + key + "' must be a scalar"));
    return n.Scalar();
  }

  /// The sequence `key` of `count` numbers (any count when count < 0).
  std::vector<double> numbers(const std::string& key, int count,
                              const std::vector<std::string>& fields) const {
    const YAML::Node n = required(key);
    const int at = lineOf(n, line());
    if (!n.IsSequence())
      throw InputError(atLine(name_, at, "'" + key + "' must be a list of numbers"));
    if (count >= 0 && static_cast<int>(n.size()) != count)
      throw InputError(atLine(name_, at,
                              "'" + key + "' needs " + std::to_string(count) + " numbers, found " +
                                  std::to_string(n.size())));
    std::vector<double> v;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const std::string field =
          key + " " + (i < fields.size() ? fields[i] : "[" + std::to_string(i) + "]");
      if (!n[i].IsScalar())
        throw InputError(atLine(name_, lineOf(n[i], at), field + " must be a number"));
      v.push_back(detail::parseNumber(n[i].Scalar(), name_, lineOf(n[i], at), field));
    }
    return v;
  }

  bool has(const std::string& key) const { return static_cast<bool>(std::as_const(node_)[key]); }

 private:
  YAML::Node node_;
  std::string name_;
};

}  // namespace

GeometricCalibration parseKalibrCameraYaml(const std::string& text, const std::string& name,
                                           const std::string& camera) {
  YAML::Node root;
  try {
    root = YAML::Load(withoutOpenCvDirective(text));
  } catch (const YAML::Exception& e) {
    throw InputError(atLine(name, e.mark.line >= 0 ? e.mark.line + 1 : 1, "YAML: " + e.msg));
  }
  if (!root.IsMap()) throw InputError(name + ": not a YAML map of camera parameters");
  const YAML::Node& croot = root;
  const bool flat = static_cast<bool>(croot["camera_model"]);
  const YAML::Node node = flat ? croot : croot[camera];
  if (!flat && (!node || !node.IsMap()))
    throw InputError(name + ": neither a camera_model key (EuRoC sensor.yaml) nor a '" + camera +
                     "' section (Kalibr camchain)");
  const CameraNode cam(node, name);

  const std::string model = detail::toLower(cam.scalar("camera_model"));
  if (model != "pinhole")
    throw InputError(atLine(name, lineOf(node["camera_model"], cam.line()),
                            "camera_model '" + model +
                                "' is not supported (only pinhole, with "
                                "radtan, equidistant, fov or no distortion)"));

  GeometricCalibration calib;
  CameraIntrinsics& in = calib.input;
  const auto k = cam.numbers("intrinsics", 4, {"fu", "fv", "cu", "cv"});
  const auto res = cam.required("resolution");
  const int res_line = lineOf(res, cam.line());
  if (!res.IsSequence() || res.size() != 2)
    throw InputError(atLine(name, res_line, "'resolution' must be [width, height]"));
  for (std::size_t i = 0; i < 2; ++i)
    if (!res[i].IsScalar())
      throw InputError(atLine(name, res_line, "'resolution' must be [width, height]"));
  in.width = detail::parsePositiveInt(res[0].Scalar(), name, res_line, "resolution width");
  in.height = detail::parsePositiveInt(res[1].Scalar(), name, res_line, "resolution height");
  for (int i = 0; i < 2; ++i)
    if (k[i] <= 0)
      throw InputError(atLine(name, lineOf(node["intrinsics"], cam.line()),
                              std::string(i == 0 ? "intrinsics fu" : "intrinsics fv") +
                                  " must be positive (got " + detail::formatNumber(k[i]) + ")"));
  in.fx = k[0];
  in.fy = k[1];
  in.cx = k[2];
  in.cy = k[3];

  const std::string dist_model =
      cam.has("distortion_model") ? detail::toLower(cam.scalar("distortion_model")) : "none";
  const std::string coeff_key =
      cam.has("distortion_coefficients") ? "distortion_coefficients" : "distortion_coeffs";
  const int dist_line = lineOf(node["distortion_model"], cam.line());
  if (dist_model == "radtan" || dist_model == "radial-tangential") {
    in.model = CameraModelType::RadTan;
    in.distortion = cam.numbers(coeff_key, 4, {"k1", "k2", "p1", "p2"});
  } else if (dist_model == "equidistant") {
    in.model = CameraModelType::Equidistant;
    in.distortion = cam.numbers(coeff_key, 4, {"k1", "k2", "k3", "k4"});
  } else if (dist_model == "fov") {
    in.model = CameraModelType::Fov;
    in.distortion = cam.numbers(coeff_key, 1, {"omega"});
  } else if (dist_model == "none") {
    in.model = CameraModelType::Pinhole;
    if (cam.has(coeff_key)) {
      const auto d = cam.numbers(coeff_key, -1, {});
      if (std::any_of(d.begin(), d.end(), [](double x) { return x != 0.0; }))
        throw InputError(atLine(name, lineOf(node[coeff_key], dist_line),
                                "distortion_model none with non-zero " + coeff_key));
    }
  } else {
    throw InputError(atLine(name, dist_line,
                            "distortion_model '" + dist_model +
                                "' is not supported (radtan, radial-tangential, equidistant, "
                                "fov or none)"));
  }
  try {
    validateIntrinsics(in);
  } catch (const InputError& e) {
    throw InputError(atLine(name, dist_line, e.what()));
  }

  const bool distorted =
      std::any_of(in.distortion.begin(), in.distortion.end(), [](double x) { return x != 0.0; });
  calib.output.mode = distorted ? OutputMode::Crop : OutputMode::None;
  calib.output.width = in.width;
  calib.output.height = in.height;
  return calib;
}

GeometricCalibration readKalibrCameraYaml(const std::string& path, const std::string& camera) {
  return parseKalibrCameraYaml(detail::readTextFile(path), path, camera);
}

std::string formatKalibrCameraYaml(const GeometricCalibration& calibration,
                                   const std::string& camera) {
  const CameraIntrinsics& in = calibration.input;
  validateIntrinsics(in);
  using detail::formatNumber;
  const char* model = "none";
  switch (in.model) {
    case CameraModelType::Pinhole:
      break;
    case CameraModelType::RadTan:
      model = "radtan";
      break;
    case CameraModelType::Equidistant:
      model = "equidistant";
      break;
    case CameraModelType::Fov:
      model = "fov";
      break;
  }
  std::string coeffs;
  for (const double d : in.distortion) coeffs += (coeffs.empty() ? "" : ", ") + formatNumber(d);
  return camera + ":\n  camera_model: pinhole\n  intrinsics: [" + formatNumber(in.fx) + ", " +
         formatNumber(in.fy) + ", " + formatNumber(in.cx) + ", " + formatNumber(in.cy) +
         "]\n  distortion_model: " + model + "\n  distortion_coeffs: [" + coeffs +
         "]\n  resolution: [" + std::to_string(in.width) + ", " + std::to_string(in.height) + "]\n";
}

void writeKalibrCameraYaml(const std::string& path, const GeometricCalibration& calibration,
                           const std::string& camera) {
  std::string text;
  try {
    text = formatKalibrCameraYaml(calibration, camera);
  } catch (const InputError& e) {
    throw InputError(path + ": not written: " + e.what());
  }
  detail::writeTextFile(path, text);
}

}  // namespace ldsm::calib
