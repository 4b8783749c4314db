#include "py_config.h"

#include <sstream>
#include <string>

#include "ldsm/drivers/config_yaml.h"
#include "ldsm/error.h"

namespace ldsm::python {
namespace {

/// A dict as YAML text (nested dicts as sections), for the configuration's own parser and
/// validation.
void appendYaml(const py::dict& d, int indent, std::ostringstream& out) {
  for (const auto& item : d) {
    if (!py::isinstance<py::str>(item.first))
      throw ConfigError("configuration keys must be strings, got " +
                        std::string(py::str(py::repr(item.first))));
    const std::string key = py::str(item.first);
    out << std::string(static_cast<std::size_t>(indent), ' ') << key << ":";
    const py::handle v = item.second;
    if (py::isinstance<py::dict>(v)) {
      out << "\n";
      appendYaml(py::reinterpret_borrow<py::dict>(v), indent + 2, out);
    } else if (py::isinstance<py::bool_>(v)) {
      out << (v.cast<bool>() ? " true\n" : " false\n");
    } else if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) {
      out << " " << std::string(py::str(py::repr(v))) << "\n";
    } else if (py::isinstance<py::str>(v)) {
      out << " \"" << std::string(py::str(v)) << "\"\n";
    } else {
      throw ConfigError("configuration key " + key + ": unsupported value " +
                        std::string(py::str(py::repr(v))));
    }
  }
}

}  // namespace

Config toConfig(const py::handle& value) {
  if (value.is_none()) return Config{};
  if (py::isinstance<Config>(value)) return value.cast<Config>();
  if (py::isinstance<py::dict>(value)) {
    std::ostringstream yaml;
    appendYaml(py::reinterpret_borrow<py::dict>(value), 0, yaml);
    return drivers::parseConfigYaml(yaml.str(), "configuration dict");
  }
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__"))
    return drivers::loadConfigYaml(py::str(value));
  throw ConfigError("configuration must be None, an ldsm.Config, a dict or a YAML file path");
}

void bindConfig(py::module_& m) {
  py::class_<Config>(m, "Config",
                     "The engine's configuration (see `ldsm config --print-defaults`).")
      .def(py::init([](const py::object& value) { return toConfig(value); }),
           py::arg("value") = py::none(),
           "Defaults, or from a dict of sections, a YAML file path or another Config.")
      .def_static(
          "from_yaml", [](const std::string& path) { return drivers::loadConfigYaml(path); },
          py::arg("path"))
      .def_static(
          "from_yaml_text",
          [](const std::string& text) { return drivers::parseConfigYaml(text, "YAML text"); },
          py::arg("text"))
      .def("to_yaml", [](const Config& c) { return drivers::configToYaml(c); })
      .def_property(
          "deterministic", [](const Config& c) { return c.system.deterministic; },
          [](Config& c, bool v) { c.system.deterministic = v; },
          "one thread, bit-identical results (as `ldsm run --deterministic`)")
      .def_property(
          "live", [](const Config& c) { return c.system.live; },
          [](Config& c, bool v) { c.system.live = v; },
          "drop the oldest queued frame when tracking falls behind")
      .def_property(
          "loop_closure", [](const Config& c) { return c.loop.enabled; },
          [](Config& c, bool v) { c.loop.enabled = v; })
      .def_property(
          "map_reuse", [](const Config& c) { return c.reuse.enabled; },
          [](Config& c, bool v) { c.reuse.enabled = v; })
      .def("__repr__", [](const Config& c) {
        return std::string("ldsm.Config(deterministic=") +
               (c.system.deterministic ? "True" : "False") +
               ", live=" + (c.system.live ? "True" : "False") +
               ", loop_closure=" + (c.loop.enabled ? "True" : "False") +
               ", map_reuse=" + (c.reuse.enabled ? "True" : "False") + ")";
      });
}

}  // namespace ldsm::python
