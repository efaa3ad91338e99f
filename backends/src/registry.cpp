#include "owval/backends/registry.hpp"

#include <cstdlib>

#include "owval/base/errors.hpp"
#include "owval/base/input_file.hpp"
#include "owval/base/json_file.hpp"
#include "owval/base/one_line.hpp"

namespace owval::backends {
namespace fs = std::filesystem;

const char* KindName(BackendKind kind) {
  switch (kind) {
    case BackendKind::kBuiltin:
      return "built-in";
    case BackendKind::kCommand:
      return "command";
    case BackendKind::kStore:
      return "store";
  }
  return "?";
}

nlohmann::json Backend::ToJson() const {
  nlohmann::json j = {{"name", name}, {"kind", KindName(kind)}, {"defined_in", defined_in}};
  if (!description.empty()) j["description"] = description;
  if (kind == BackendKind::kBuiltin) j["engine_backend"] = engine_backend;
  if (kind == BackendKind::kCommand) {
    j["command"] = command;
    j["working_directory"] = working_directory.string();
    j["output"] = output;
    j["layout"] = layout;
    if (!set_defaults.empty()) j["set"] = set_defaults;
    if (!store.empty()) j["fallback_store"] = store.string();
  }
  if (kind == BackendKind::kStore) j["store"] = store.string();
  return j;
}

RegistryOptions RegistryOptionsFromEnvironment(const fs::path& file) {
  RegistryOptions o;
  o.file = file;
  o.current_directory = fs::current_path();
  if (const char* x = std::getenv("XDG_CONFIG_HOME")) o.xdg_config_home = x;
  if (const char* h = std::getenv("HOME")) o.home = h;
  return o;
}

fs::path RegistryFile(const RegistryOptions& o) {
  std::error_code ec;
  if (!o.file.empty()) {
    RequireInputFile(o.file, "a backends file (JSON: docs/backends.md)");
    return o.file;
  }
  if (fs::is_regular_file(o.current_directory / "owval-backends.json", ec))
    return o.current_directory / "owval-backends.json";
  const fs::path config =
      o.xdg_config_home.empty() ? fs::path(o.home) / ".config" : fs::path(o.xdg_config_home);
  if ((!o.xdg_config_home.empty() || !o.home.empty()) &&
      fs::is_regular_file(config / "owval" / "backends.json", ec))
    return config / "owval" / "backends.json";
  return {};
}

namespace {

std::vector<Backend> Builtins() {
  Backend owval;
  owval.name = "owval";
  owval.engine_backend = "pcisph";
  owval.description = "owval's engine, PCISPH (Sibernetic's scheme), in process; alias pcisph";
  Backend xpbd;
  xpbd.name = "xpbd";
  xpbd.engine_backend = "xpbd";
  xpbd.description = "owval's engine with the XPBD scheme, in process";
  Backend wcsph;
  wcsph.name = "wcsph";
  wcsph.engine_backend = "wcsph";
  wcsph.description =
      "owval's engine with the WCSPH scheme (docs/wcsph.md), in process; liquid and walls only";
  for (Backend* b : {&owval, &xpbd, &wcsph}) b->defined_in = "built in";
  return {owval, xpbd, wcsph};
}

fs::path ResolvePath(const std::string& text, const fs::path& base, const std::string& home) {
  if (text.rfind("~/", 0) == 0) return fs::path(home) / text.substr(2);
  const fs::path p(text);
  return p.is_relative() ? base / p : p;
}

std::string StringField(const nlohmann::json& entry, const char* key, const std::string& where) {
  if (!entry.contains(key)) return "";
  if (!entry[key].is_string()) throw InputError(where, 0, std::string(key) + ": expected a string");
  return entry[key].get<std::string>();
}

Backend ParseEntry(const std::string& name, const nlohmann::json& e, const fs::path& file,
                   const std::string& home) {
  const std::string where = file.string() + ": backend \"" + name + "\"";
  if (!e.is_object()) throw InputError(where, 0, "expected an object");
  Backend b;
  b.name = name;
  b.defined_in = file.string();
  const fs::path base = file.parent_path();
  b.command = StringField(e, "command", where);
  b.description = StringField(e, "description", where);
  if (const std::string s = StringField(e, "store", where); !s.empty())
    b.store = ResolvePath(s, base, home);
  b.kind = b.command.empty() ? BackendKind::kStore : BackendKind::kCommand;
  if (b.command.empty() && b.store.empty())
    throw InputError(where, 0, "expected \"command\" or \"store\"");
  if (const std::string w = StringField(e, "working_directory", where); !w.empty())
    b.working_directory = ResolvePath(w, base, home);
  if (const std::string o = StringField(e, "output", where); !o.empty()) b.output = o;
  if (const std::string l = StringField(e, "layout", where); !l.empty()) b.layout = l;
  if (b.layout != "auto" && b.layout != "opencl" && b.layout != "native" && b.layout != "hdf5")
    throw InputError(where, 0, "layout: expected auto, opencl, native or hdf5, got " + b.layout);
  if (e.contains("set")) {
    if (!e["set"].is_object()) throw InputError(where, 0, "set: expected an object");
    for (const auto& [k, v] : e["set"].items())
      b.set_defaults[k] = v.is_string() ? v.get<std::string>() : v.dump();
  }
  return b;
}

}  // namespace

Registry ParseRegistry(const nlohmann::json& document, const fs::path& file,
                       const std::string& home) {
  Registry r;
  r.file = file;
  r.backends = Builtins();
  if (!document.is_object() || !document.contains("backends") || !document["backends"].is_object())
    throw InputError(file.string(), 0, "expected {\"backends\": {NAME: {...}}}");
  for (const auto& [name, entry] : document["backends"].items()) {
    // A name is typed on the command line and printed in tables: a newline or an escape in it
    // went to the terminal raw.
    const bool plain = !name.empty() && name.size() <= 64 && name.front() != '.' &&
                       name.find_first_not_of(
                           "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                           "0123456789_.-") == std::string::npos;
    if (!plain)
      throw InputError(file.string(), 0,
                       "backend \"" + OneLine(name, 40) +
                           "\": expected a name of letters, digits, '_', '-' and '.'");
    for (const std::string& taken : r.Names())
      if (taken == name || name == "pcisph")
        throw InputError(file.string(), 0, "backend \"" + name + "\" redefines a built-in name");
    r.backends.push_back(ParseEntry(name, entry, file, home));
  }
  return r;
}

Registry LoadRegistry(const RegistryOptions& options) {
  const fs::path file = RegistryFile(options);
  Registry r;
  r.backends = Builtins();
  if (file.empty()) return r;
  return ParseRegistry(ReadJsonFile(file), file, options.home);
}

const Backend& Registry::Find(const std::string& name) const {
  const std::string key = name == "pcisph" ? "owval" : name;
  for (const Backend& b : backends)
    if (b.name == key) return b;
  std::string known;
  for (const std::string& n : Names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown backend \"" + name + "\"; known: " + known +
                   (file.empty() ? " (no backends file found)" : " (from " + file.string() + ")"));
}

std::vector<std::string> Registry::Names() const {
  std::vector<std::string> names;
  for (const Backend& b : backends) names.push_back(b.name);
  return names;
}

nlohmann::json Registry::ToJson() const {
  nlohmann::json all = nlohmann::json::array();
  for (const Backend& b : backends) all.push_back(b.ToJson());
  return all;
}

std::string Registry::ToText() const {
  std::string text = "backends file: " + (file.empty() ? "(none)" : file.string()) + "\n";
  for (const Backend& b : backends) {
    const std::string what = b.kind == BackendKind::kBuiltin ? "engine " + b.engine_backend
                             : b.kind == BackendKind::kStore ? "store " + b.store.string()
                                                             : "command " + b.command;
    auto padded = [](std::string field, std::size_t width) {
      if (field.size() < width) field.resize(width, ' ');
      return field + " ";
    };
    text += padded(b.name, 12) + padded(KindName(b.kind), 9) + what + "\n";
  }
  return text;
}

}  // namespace owval::backends
