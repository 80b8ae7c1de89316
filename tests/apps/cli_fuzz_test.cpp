// Fuzz-style test of every command that loads a model: truncations, byte flips and crafted
// headers of the shipped models (seeded, a few dozen runs). A command may succeed on a file
// that a flip left valid; otherwise it exits 2, 3 or 4 with one error line and writes nothing.
#include <cstdint>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "support/gltf_edit.hpp"

namespace cgamesh_cli_test {
namespace {

struct Mutant {
  std::string name;   ///< file name, with the model's extension
  std::string bytes;  ///< contents
};

/// Truncations, byte flips and crafted headers of `model`, drawn from `rng`.
std::vector<Mutant> mutants(const fs::path& model, std::mt19937& rng, int flips, int truncations) {
  const std::string bytes = read_file(model), ext = model.extension().string(), stem = model.stem().string();
  std::vector<Mutant> out;
  std::uniform_int_distribution<std::size_t> position(0, bytes.size() - 1);
  std::uniform_int_distribution<int> byte(0, 255), count(1, 8);
  for (int i = 0; i < truncations; ++i)
    out.push_back({stem + "_cut" + std::to_string(i) + ext, bytes.substr(0, position(rng))});
  for (int i = 0; i < flips; ++i) {
    Mutant m{stem + "_flip" + std::to_string(i) + ext, bytes};
    for (int k = count(rng); k > 0; --k) m.bytes[position(rng)] = static_cast<char>(byte(rng));
    out.push_back(std::move(m));
  }
  if (ext == ".glb") {
    // Header fields: total length and the JSON chunk's length, made huge.
    for (const std::size_t offset : {std::size_t{8}, std::size_t{12}}) {
      Mutant m{stem + "_header" + std::to_string(offset) + ext, bytes};
      const std::uint32_t huge = 0xfffffff0u;
      std::memcpy(m.bytes.data() + offset, &huge, sizeof huge);
      out.push_back(std::move(m));
    }
  }
  return out;
}

/// Lines of stderr that are not warnings.
std::vector<std::string> error_lines(const std::string& err) {
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("cgamesh: warning:", 0) != 0) lines.push_back(line);
  return lines;
}

/// The commands each mutant of CesiumMan goes through, in turn; {} stands for the input and
/// OUT for a file in the output directory.
const std::vector<std::vector<std::string>>& commands() {
  static const std::vector<std::vector<std::string>> list = {
      {"info", "{}", "--json"},
      {"pose", "{}", "-o", "OUT.obj"},
      {"convert", "{}", "-o", "OUT.glb"},
      {"animate", "{}", "--key", "0:0:rotate=0,0,1,10", "--key", "1:0:rotate=0,0,1,40", "-o", "OUT.glb"},
      {"cut", "{}", "--plane", "0,1,0,0.7", "--cap", "-o", "OUT_a.glb", "OUT_b.glb"},
      {"drill", "{}", "--tip", "0.3,1.0,0", "--base", "-0.3,1.0,0", "--radius", "0.05", "-o", "OUT.glb"},
      {"tear", "{}", "--scalpel", "0.3,1.2,-0.1,0.0,1.2,-0.1", "--scalpel", "0.3,1.0,-0.1,0.0,1.0,-0.1", "-o",
       "OUT.obj"},
      {"deform", "{}", "--spec", std::string(CGAMESH_DATA_DIR) + "/specs/cesiumman_bend.json", "-o", "OUT.obj"},
  };
  return list;
}

void run_mutant(const Failure& f, const Mutant& m, const std::vector<std::string>& command) {
  const fs::path input = f.inputs / m.name;
  { std::ofstream(input, std::ios::binary) << m.bytes; }
  std::vector<std::string> args;
  for (const std::string& a : command)
    args.push_back(a == "{}" ? input.string() : a.rfind("OUT", 0) == 0 ? (f.outputs / (m.name + a)).string() : a);
  const Result r = run_cli(args, f.inputs.path());
  SCOPED_TRACE(r.command);
  ASSERT_TRUE(r.code == 0 || r.code == 2 || r.code == 3 || r.code == 4) << r;
  if (r.code == 0) {
    if (command[0] == "info") {
      EXPECT_TRUE(nlohmann::json::accept(r.out)) << r;
    }
  } else {
    const std::vector<std::string> lines = error_lines(r.err);
    ASSERT_EQ(lines.size(), 1u) << r;
    EXPECT_EQ(lines[0].rfind("cgamesh: ", 0), 0u) << r;
    EXPECT_GT(lines[0].size(), std::string("cgamesh: ").size() + 10) << r;
    EXPECT_TRUE(f.outputs.entries().empty()) << r;
  }
  for (const std::string& e : f.outputs.entries()) fs::remove(f.outputs / e);
  fs::remove(input);
}

TEST(CliFuzz, MutatedCesiumManThroughEveryLoadingCommand) {
  std::mt19937 rng(15);
  Failure f;
  const auto list = mutants(cgamesh_test::demo_model(), rng, 30, 10);
  for (std::size_t i = 0; i < list.size(); ++i) run_mutant(f, list[i], commands()[i % commands().size()]);
}

TEST(CliFuzz, MutatedTextAndOtherFormats) {
  std::mt19937 rng(16);
  Failure f;
  for (const char* model : {"cow.obj", "arm_16k.ply", "RiggedSimple.glb"}) {
    const auto list = mutants(cgamesh_test::asset(model), rng, 3, 2);
    for (std::size_t i = 0; i < list.size(); ++i) run_mutant(f, list[i], commands()[i % 3]);  // info, pose, convert
  }
}

// A key that scales a joint by zero breaks the file for every command, not only for those
// that pose the clip: `cut` at the bind pose exited 0 where `pose` exited 2.
TEST(CliFuzz, ZeroScaleKeyIsBadInputInEveryCommand) {
  Failure f;
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::demo_model());
  for (const tinygltf::AnimationChannel& c : m.animations[0].channels) {
    if (c.target_path != "scale") continue;
    const auto& sampler = m.animations[0].samplers[static_cast<std::size_t>(c.sampler)];
    const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(sampler.output)];
    const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    auto& data = m.buffers[static_cast<std::size_t>(v.buffer)].data;
    const float zero = 0;
    std::memcpy(data.data() + v.byteOffset + a.byteOffset, &zero, sizeof zero);
    break;
  }
  const fs::path file = cgamesh_test::write_glb(std::move(m), f.inputs / "zero_scale.glb");
  for (const auto& command : commands()) {
    std::vector<std::string> args;
    for (const std::string& a : command)
      args.push_back(a == "{}" ? file.string() : a.rfind("OUT", 0) == 0 ? (f.outputs / a).string() : a);
    expect_failure(f, args, 3, "a zero or mirroring scale has no versor", f.outputs / "OUT.glb");
  }
}

}  // namespace
}  // namespace cgamesh_cli_test
