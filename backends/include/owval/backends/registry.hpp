#pragma once
// Backends by name. Built in: "owval" (alias "pcisph"), "xpbd" and "wcsph", the in-process
// engine with that scheme. User-defined ones come from one JSON file, the first found of:
// --backends FILE, ./owval-backends.json, $XDG_CONFIG_HOME/owval/backends.json (XDG default
// ~/.config):
//   {"backends": {
//      "opencl": {"command": "./Sibernetic -no_g -l_to device=cpu -f {config} timelimit={time}
//                             logstep={log_step} lpath={out}",
//                 "working_directory": "~/sibernetic", "output": "{out}/position_buffer.txt",
//                 "layout": "opencl", "store": "/data/reference", "set": {"NAME": "VALUE"}},
//      "recorded": {"store": "../shared/reference"}}}
// A command backend's "store" is its fallback when the command's program is missing. Relative
// paths are relative to the file's directory; "~/" is the home directory. docs/backends.md.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace owval::backends {

enum class BackendKind { kBuiltin, kCommand, kStore };
const char* KindName(BackendKind kind);  // "built-in" | "command" | "store"

struct Backend {
  std::string name;
  BackendKind kind = BackendKind::kBuiltin;
  std::string engine_backend;               // built-in: the engine's scheme ("pcisph", "xpbd")
  std::string command;                      // command: the template (template.hpp)
  std::filesystem::path working_directory;  // command: where it runs ("" = here)
  std::string output = "{out}/position_buffer.txt";  // command: where the trajectory lands
  std::string layout = "auto";                       // auto | opencl | native | hdf5
  std::map<std::string, std::string> set_defaults;   // values of {set:NAME}
  std::filesystem::path store;  // store: recorded runs; command: fallback when program missing
  std::string description;
  std::string defined_in;  // "built in" or the registry file
  nlohmann::json ToJson() const;
};

struct RegistryOptions {
  std::filesystem::path file;  // --backends (must exist when given)
  std::filesystem::path current_directory = ".";
  std::string xdg_config_home;  // "" = unset
  std::string home;             // for the XDG default and "~/"
};
// Options from the process environment (XDG_CONFIG_HOME, HOME) and the current directory.
RegistryOptions RegistryOptionsFromEnvironment(const std::filesystem::path& file);

// The registry file the options select, or "" when there is none.
std::filesystem::path RegistryFile(const RegistryOptions& options);

struct Registry {
  std::filesystem::path file;     // the user file read ("" = built-ins only)
  std::vector<Backend> backends;  // built-ins first
  // The backend by name or alias; InputError listing the known names otherwise.
  const Backend& Find(const std::string& name) const;
  std::vector<std::string> Names() const;
  nlohmann::json ToJson() const;  // every backend's definition
  std::string ToText() const;     // the file, then one line per backend: name, kind, what it runs
};

// Built-ins plus the selected file's entries. InputError naming the file and entry for a
// malformed entry or one that redefines a built-in name.
Registry LoadRegistry(const RegistryOptions& options);
Registry ParseRegistry(const nlohmann::json& document, const std::filesystem::path& file,
                       const std::string& home);

}  // namespace owval::backends
