#include "ldsm/drivers/config_yaml.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <type_traits>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

std::string where(const std::string& name, const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  return m.is_null() ? name : name + ":" + std::to_string(m.line + 1);
}

/// Overrides fields of a Config from a YAML map, rejecting unknown keys and bad types.
class YamlReader {
 public:
  YamlReader(const YAML::Node& root, std::string name) : name_(std::move(name)) {
    nodes_.push_back(root);
  }

  template <typename S>
  void section(const char* key, S& s, const char* /*help*/) {
    const YAML::Node& parent = nodes_.back();
    visited_.back().insert(key);
    const YAML::Node node = parent[key];
    if (!node) return;
    if (!node.IsMap())
      throw ConfigError(where(name_, node) + ": '" + path(key) + "' must be a map of settings");
    const std::string saved = prefix_;
    prefix_ += std::string(key) + ".";
    nodes_.push_back(node);
    visited_.emplace_back();
    s.visit(*this);
    checkUnknown();
    visited_.pop_back();
    nodes_.pop_back();
    prefix_ = saved;
  }

  void field(const char* key, bool& value, const char* /*help*/) {
    const YAML::Node node = lookup(key);
    if (!node) return;
    if (!YAML::convert<bool>::decode(node, value))
      throw ConfigError(where(name_, node) + ": '" + path(key) + "' must be true or false, got '" +
                        scalar(node) + "'");
  }

  template <typename T>
  void field(const char* key, T& value, Range<T> range, const char* /*help*/) {
    const YAML::Node node = lookup(key);
    if (!node) return;
    T parsed{};
    if (!node.IsScalar() || !YAML::convert<T>::decode(node, parsed)) {
      const char* kind = std::is_integral<T>::value ? "an integer" : "a number";
      throw ConfigError(where(name_, node) + ": '" + path(key) + "' must be " + kind + " in [" +
                        toString(range.min) + ", " + toString(range.max) + "], got '" +
                        scalar(node) + "'");
    }
    if (!(parsed >= range.min && parsed <= range.max))
      throw ConfigError(where(name_, node) + ": '" + path(key) + "' = " + scalar(node) +
                        " is outside the allowed range [" + toString(range.min) + ", " +
                        toString(range.max) + "]");
    value = parsed;
  }

  /// Rejects keys of the current map that no field or section claimed.
  void checkUnknown() const {
    const YAML::Node& node = nodes_.back();
    for (auto it = node.begin(); it != node.end(); ++it) {
      // A key that is itself a list or a map ("[a, b]: 1", "? {x: 1}") names no setting.
      if (!it->first.IsScalar())
        throw ConfigError(where(name_, it->first) + ": a key " +
                          (prefix_.empty() ? std::string("at the top level")
                                           : "in '" + prefix_.substr(0, prefix_.size() - 1) + "'") +
                          " is a list or a map, not a setting's name");
      const std::string key = it->first.Scalar();
      if (!visited_.back().count(key)) {
        std::string known;
        for (const auto& k : visited_.back()) known += (known.empty() ? "" : ", ") + k;
        throw ConfigError(where(name_, it->first) + ": unknown key '" + path(key.c_str()) +
                          "' (known here: " + known + ")");
      }
    }
  }

 private:
  YAML::Node lookup(const char* key) {
    visited_.back().insert(key);
    return nodes_.back()[key];
  }
  std::string path(const char* key) const { return prefix_ + key; }
  static std::string scalar(const YAML::Node& n) {
    return n.IsScalar() ? n.Scalar() : "<not a value>";
  }
  template <typename T>
  static std::string toString(T v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  std::string name_;
  std::string prefix_;
  std::vector<YAML::Node> nodes_;
  std::vector<std::set<std::string>> visited_{1};
};

/// Writes the configuration as commented YAML.
class YamlPrinter {
 public:
  template <typename S>
  void section(const char* key, S& s, const char* help) {
    os_ << "\n# " << help << "\n" << key << ":\n";
    s.visit(*this);
  }
  void field(const char* key, bool& value, const char* help) {
    os_ << "  # " << help << " (true or false)\n  " << key << ": " << (value ? "true" : "false")
        << "\n";
  }
  template <typename T>
  void field(const char* key, T& value, Range<T> range, const char* help) {
    os_ << "  # " << help << " [" << range.min << ", " << range.max << "]\n  " << key << ": ";
    if constexpr (std::is_floating_point<T>::value)
      os_.precision(std::numeric_limits<T>::max_digits10);
    os_ << value << "\n";
    os_.precision(6);
  }
  std::string str() const { return os_.str(); }

 private:
  std::ostringstream os_;
};

}  // namespace

Config parseConfigYaml(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  Config config;
  if (root.IsNull()) return config;  // an empty file means all defaults
  if (!root.IsMap()) throw ConfigError(name + ": the configuration must be a YAML map of sections");
  YamlReader reader(root, name);
  config.visit(reader);
  reader.checkUnknown();
  try {
    validateConfig(config);
  } catch (const ConfigError& e) {
    throw ConfigError(name + ": " + e.what());
  }
  return config;
}

Config loadConfigYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open the configuration file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseConfigYaml(ss.str(), path);
}

std::string configToYaml(const Config& config) {
  Config copy = config;
  YamlPrinter printer;
  copy.visit(printer);
  return "# ldsm configuration. Keys left out keep their defaults.\n" + printer.str();
}

}  // namespace ldsm::drivers
