// `ldsm config`: print the default configuration, or check a configuration file.
#include <cstdio>
#include <fstream>
#include <string>

#include "commands.h"
#include "ldsm/config.h"
#include "ldsm/drivers/config_yaml.h"
#include "ldsm/error.h"

namespace ldsm::app {

void addConfigCommand(CLI::App& app, CommandResult& result) {
  auto* cmd = app.add_subcommand("config", "Print the default configuration or check a file");
  auto print_defaults = std::make_shared<bool>(false);
  auto check = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  cmd->add_flag("--print-defaults", *print_defaults, "Write the full default configuration (YAML)");
  cmd->add_option("--check", *check, "Validate FILE and print the effective configuration");
  cmd->add_option("--out", *out, "Write to FILE instead of standard output");
  cmd->callback([=, &result]() {
    if (!*print_defaults && check->empty())
      throw ConfigError("ldsm config: give --print-defaults or --check FILE");
    const Config config = check->empty() ? Config{} : drivers::loadConfigYaml(*check);
    const std::string yaml = drivers::configToYaml(config);
    if (out->empty()) {
      std::fputs(yaml.c_str(), stdout);
    } else {
      std::ofstream f(*out);
      if (!(f << yaml)) throw InputError(*out + ": cannot write the configuration");
    }
    if (!check->empty()) std::fprintf(stderr, "%s: configuration is valid\n", check->c_str());
    result.exit_code = 0;
  });
}

}  // namespace ldsm::app
