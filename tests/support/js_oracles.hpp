#pragma once
// The JavaScript oracles of tests/oracle/js run under node: the Khronos glTF validator and
// three.js skinning. Tests skip when node or the npm packages are missing.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cgamesh_test {

inline std::filesystem::path js_oracles() { return std::filesystem::path(CGAMESH_JS_ORACLES); }

inline bool node_available() { return std::system("node --version > /dev/null 2>&1") == 0; }

inline bool validator_available() {
  return std::filesystem::exists(js_oracles() / "node_modules" / "gltf-validator") && node_available();
}

inline bool three_available() { return std::filesystem::exists(js_oracles() / "node_modules" / "three") && node_available(); }

/// Runs the Khronos validator on `file`; returns its exit status (0: no errors) and puts its
/// report in `log`.
inline int validate_gltf(const std::filesystem::path& file, std::string& log) {
  const std::filesystem::path log_file = file.string() + ".validator.log";
  const std::string cmd = "node \"" + (js_oracles() / "validate_gltf.mjs").string() + "\" \"" + file.string() +
                          "\" > \"" + log_file.string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log_file);
  std::stringstream text;
  text << in.rdbuf();
  log = text.str();
  std::filesystem::remove(log_file);
  return status;
}

/// three.js' posed vertices of `model` (clip 0) at `times`: skin_reference.mjs's JSON. Weights
/// are normalised, as cgamesh does on load (some sample models store rows not summing to 1).
inline nlohmann::json three_reference(const std::filesystem::path& model, const std::vector<double>& times) {
  const std::filesystem::path out = model.string() + ".three.json";
  std::ostringstream list;
  for (std::size_t i = 0; i < times.size(); ++i) list << (i ? "," : "") << times[i];
  const std::string cmd = "node \"" + (js_oracles() / "skin_reference.mjs").string() + "\" \"" + model.string() +
                          "\" \"" + out.string() + "\" --weights normalized --times " + list.str() + " 2> /dev/null";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("three.js oracle failed: " + cmd);
  std::ifstream in(out);
  nlohmann::json j = nlohmann::json::parse(in);
  std::filesystem::remove(out);
  return j;
}

}  // namespace cgamesh_test
