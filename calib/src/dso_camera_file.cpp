#include "ldsm/calib/dso_camera_file.h"

#include <algorithm>
#include <array>
#include <vector>

#include "ldsm/camera/camera_model.h"
#include "ldsm/error.h"
#include "text_file.h"

namespace ldsm::calib {
namespace {

using detail::TextLine;

struct ModelSyntax {
  const char* keyword;  ///< lower case
  CameraModelType type;
  std::vector<std::string> fields;
};

const std::vector<ModelSyntax>& modelSyntaxes() {
  static const std::vector<ModelSyntax> kSyntaxes = {
      {"pinhole", CameraModelType::Pinhole, {"fx", "fy", "cx", "cy"}},
      {"radtan", CameraModelType::RadTan, {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"}},
      {"equidistant",
       CameraModelType::Equidistant,
       {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"}},
      {"kannalabrandt",
       CameraModelType::Equidistant,
       {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"}},
      {"fov", CameraModelType::Fov, {"fx", "fy", "cx", "cy", "omega"}},
      {"atan", CameraModelType::Fov, {"fx", "fy", "cx", "cy", "omega"}},
  };
  return kSyntaxes;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

bool looksNumeric(const std::string& token) {
  const char c = token[0];
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

void checkPositive(double v, const std::string& field, const std::string& name, int line) {
  if (v <= 0)
    throw InputError(
        atLine(name, line, field + " must be positive (got " + detail::formatNumber(v) + ")"));
}

CameraIntrinsics parseIntrinsicsLine(const TextLine& line, const std::string& name) {
  CameraIntrinsics in;
  std::vector<std::string> numbers = line.tokens;
  std::vector<std::string> fields;
  std::string model_text;
  if (looksNumeric(line.tokens[0])) {
    // Old DSO style: fx fy cx cy omega (FOV, or pinhole when omega == 0).
    model_text = "old-style intrinsics";
    fields = {"fx", "fy", "cx", "cy", "omega"};
    if (numbers.size() != 5)
      throw InputError(atLine(name, line.number,
                              "old-style intrinsics need 5 numbers (fx fy cx cy omega), found " +
                                  std::to_string(numbers.size())));
    in.model = CameraModelType::Fov;
  } else {
    const std::string keyword = detail::toLower(line.tokens[0]);
    const auto& syntaxes = modelSyntaxes();
    const auto it = std::find_if(syntaxes.begin(), syntaxes.end(),
                                 [&](const ModelSyntax& s) { return keyword == s.keyword; });
    if (it == syntaxes.end())
      throw InputError(atLine(name, line.number,
                              "unknown camera model '" + line.tokens[0] +
                                  "' (expected Pinhole, RadTan, EquiDistant, KannalaBrandt or "
                                  "FOV)"));
    numbers.erase(numbers.begin());
    in.model = it->type;
    fields = it->fields;
    model_text = line.tokens[0];
    // DSO writes "Pinhole fx fy cx cy 0": accept the trailing 0.
    const bool pinhole_with_zero = it->type == CameraModelType::Pinhole && numbers.size() == 5;
    if (numbers.size() != fields.size() && !pinhole_with_zero)
      throw InputError(atLine(name, line.number,
                              model_text + " needs " + std::to_string(fields.size()) +
                                  " numbers (" + joined(fields) + "), found " +
                                  std::to_string(numbers.size())));
    if (pinhole_with_zero) {
      const double extra = detail::parseNumber(numbers[4], name, line.number, "5th value");
      if (extra != 0.0)
        throw InputError(
            atLine(name, line.number,
                   "Pinhole has no distortion: the 5th value must be 0 (got " + numbers[4] + ")"));
      numbers.pop_back();
    }
  }
  std::vector<double> v;
  for (std::size_t i = 0; i < numbers.size(); ++i)
    v.push_back(detail::parseNumber(numbers[i], name, line.number, fields[i]));
  checkPositive(v[0], "fx", name, line.number);
  checkPositive(v[1], "fy", name, line.number);
  in.fx = v[0];
  in.fy = v[1];
  in.cx = v[2];
  in.cy = v[3];
  in.distortion.assign(v.begin() + 4, v.end());
  if (in.model == CameraModelType::Fov && looksNumeric(line.tokens[0]) && in.distortion[0] == 0.0) {
    in.model = CameraModelType::Pinhole;
    in.distortion.clear();
  }
  return in;
}

std::array<int, 2> parseSizeLine(const TextLine& line, const std::string& name,
                                 const std::string& what) {
  if (line.tokens.size() != 2)
    throw InputError(atLine(name, line.number,
                            what + " size: expected 'width height', found " +
                                std::to_string(line.tokens.size()) + " values"));
  return {detail::parsePositiveInt(line.tokens[0], name, line.number, what + " width"),
          detail::parsePositiveInt(line.tokens[1], name, line.number, what + " height")};
}

RectificationSpec parseOutputLine(const TextLine& line, const std::string& name) {
  RectificationSpec out;
  const std::string first = detail::toLower(line.tokens[0]);
  if (!looksNumeric(line.tokens[0])) {
    if (line.tokens.size() == 1 && first == "crop") {
      out.mode = OutputMode::Crop;
    } else if (line.tokens.size() == 1 && first == "full") {
      out.mode = OutputMode::Full;
    } else if (line.tokens.size() == 1 && first == "none") {
      out.mode = OutputMode::None;
    } else {
      throw InputError(atLine(name, line.number,
                              "unknown output mode '" + line.tokens[0] +
                                  "' (expected crop, full, none or fx fy cx cy 0)"));
    }
    return out;
  }
  if (line.tokens.size() != 4 && line.tokens.size() != 5)
    throw InputError(atLine(name, line.number,
                            "explicit output needs 5 numbers (fx fy cx cy 0), found " +
                                std::to_string(line.tokens.size())));
  static const char* kFields[] = {"output fx", "output fy", "output cx", "output cy"};
  double v[4];
  for (int i = 0; i < 4; ++i)
    v[i] = detail::parseNumber(line.tokens[i], name, line.number, kFields[i]);
  if (line.tokens.size() == 5 &&
      detail::parseNumber(line.tokens[4], name, line.number, "output 5th value") != 0.0)
    throw InputError(atLine(
        name, line.number,
        "the output is an ideal pinhole: the 5th value must be 0 (got " + line.tokens[4] + ")"));
  checkPositive(v[0], "output fx", name, line.number);
  checkPositive(v[1], "output fy", name, line.number);
  out.mode = OutputMode::Explicit;
  out.fx = v[0];
  out.fy = v[1];
  out.cx = v[2];
  out.cy = v[3];
  out.relative = std::all_of(v, v + 4, [](double x) { return x < 1.0; });
  return out;
}

}  // namespace

GeometricCalibration parseDsoCameraFile(const std::string& text, const std::string& name) {
  const std::vector<TextLine> lines = detail::contentLines(text);
  static const char* kExpected[] = {"the camera model and intrinsics", "the input size",
                                    "the output mode (crop, full, none or fx fy cx cy 0)",
                                    "the output size"};
  if (lines.size() < 4) {
    const int missing_line = lines.empty() ? 1 : lines.back().number + 1;
    throw InputError(atLine(name, missing_line,
                            std::string("missing line ") + std::to_string(lines.size() + 1) +
                                " of camera.txt: " + kExpected[lines.size()]));
  }
  if (lines.size() > 4)
    throw InputError(
        atLine(name, lines[4].number, "unexpected content after the output size line"));

  GeometricCalibration calib;
  CameraIntrinsics& in = calib.input;
  in = parseIntrinsicsLine(lines[0], name);
  const auto input_size = parseSizeLine(lines[1], name, "input");
  in.width = input_size[0];
  in.height = input_size[1];
  if (in.fx < 1 && in.fy < 1 && in.cx < 1 && in.cy < 1) {
    // Relative intrinsics (DSO): the 0.5 moves the origin from the pixel corner to its center.
    in.fx *= in.width;
    in.fy *= in.height;
    in.cx = in.cx * in.width - 0.5;
    in.cy = in.cy * in.height - 0.5;
  }
  try {
    validateIntrinsics(in);
  } catch (const InputError& e) {
    throw InputError(atLine(name, lines[0].number, e.what()));
  }

  const std::string out_text = lines[2].tokens[0];
  calib.output = parseOutputLine(lines[2], name);
  const auto output_size = parseSizeLine(lines[3], name, "output");
  calib.output.width = output_size[0];
  calib.output.height = output_size[1];

  const OutputMode mode = calib.output.mode;
  if ((mode == OutputMode::Crop || mode == OutputMode::Full) &&
      (calib.output.width > in.width || calib.output.height > in.height))
    throw InputError(atLine(name, lines[3].number,
                            out_text + " output size " + std::to_string(calib.output.width) + "x" +
                                std::to_string(calib.output.height) +
                                " is larger than the input size " + std::to_string(in.width) + "x" +
                                std::to_string(in.height)));
  if (mode == OutputMode::None &&
      std::any_of(in.distortion.begin(), in.distortion.end(), [](double d) { return d != 0.0; }))
    throw InputError(atLine(name, lines[2].number,
                            "output mode none needs an undistorted input, but line " +
                                std::to_string(lines[0].number) +
                                " has distortion (use crop, "
                                "full or an explicit output)"));
  return calib;
}

GeometricCalibration readDsoCameraFile(const std::string& path) {
  return parseDsoCameraFile(detail::readTextFile(path), path);
}

std::string formatDsoCameraFile(const GeometricCalibration& calibration) {
  const CameraIntrinsics& in = calibration.input;
  validateIntrinsics(in);
  const RectificationSpec& out = calibration.output;
  if (out.width <= 0 || out.height <= 0)
    throw InputError("camera.txt: output size must be positive (got " + std::to_string(out.width) +
                     "x" + std::to_string(out.height) + ")");
  using detail::formatNumber;
  std::string s = cameraModelName(in.model);
  for (const double v : {in.fx, in.fy, in.cx, in.cy}) s += " " + formatNumber(v);
  for (const double v : in.distortion) s += " " + formatNumber(v);
  if (in.model == CameraModelType::Pinhole) s += " 0";
  s += "\n" + std::to_string(in.width) + " " + std::to_string(in.height) + "\n";
  switch (out.mode) {
    case OutputMode::Crop:
      s += "crop\n";
      break;
    case OutputMode::Full:
      s += "full\n";
      break;
    case OutputMode::None:
      s += "none\n";
      break;
    case OutputMode::Explicit:
      for (const double v : {out.fx, out.fy, out.cx, out.cy}) s += formatNumber(v) + " ";
      s += "0\n";
      break;
  }
  s += std::to_string(out.width) + " " + std::to_string(out.height) + "\n";
  return s;
}

void writeDsoCameraFile(const std::string& path, const GeometricCalibration& calibration) {
  std::string text;
  try {
    text = formatDsoCameraFile(calibration);
  } catch (const InputError& e) {
    throw InputError(path + ": not written: " + e.what());
  }
  detail::writeTextFile(path, text);
}

}  // namespace ldsm::calib
