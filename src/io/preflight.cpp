#include "preflight.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/errors.hpp"

#include "excerpt.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "lower_case.hpp"

namespace cgamesh::io::detail {
namespace {

/// The first word of a line.
std::string first_word(const std::string& line) {
  std::istringstream words(line);
  std::string word;
  words >> word;
  return word;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw FileError("cannot load '" + path.string() + "': " + what);
}

/// Every section (nodes, skeleton, triangles, vertexanimation) must end with "end": Assimp's
/// reader loops forever on one that runs to the end of the file.
void check_smd(const std::filesystem::path& path, std::istream& in) {
  std::string section, line;
  long section_line = 0, n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string word = lower(first_word(line));
    if (!section.empty()) {
      if (word == "end") section.clear();
    } else if (word == "nodes" || word == "skeleton" || word == "triangles" || word == "vertexanimation") {
      section = word;
      section_line = n;
    }
  }
  if (!section.empty())
    fail(path, "not a valid SMD file: its section '" + section + "' (line " + std::to_string(section_line) +
                   ") has no 'end' line");
}

/// Counts declared in a header ("numJoints 33", "element vertex 8") larger than the file's bytes
/// cannot be true: each item takes at least one byte.
void check_count(const std::filesystem::path& path, const std::string& what, std::uintmax_t count, std::uintmax_t size,
                 long line) {
  if (count > size)
    fail(path, "line " + std::to_string(line) + " declares " + std::to_string(count) + " " + what +
                   ", more than the file's " + std::to_string(size) + " bytes could hold (corrupt or truncated)");
}

/// A count word, or fail: a negative or non-numeric count is a corrupt header.
std::uintmax_t parse_count(const std::filesystem::path& path, const std::string& text, long line) {
  if (text.empty() || !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
    fail(path, "line " + std::to_string(line) + " declares a count '" + excerpt(text) + "' that is not a whole number");
  try {
    return std::stoull(text);
  } catch (const std::out_of_range&) {
    fail(path, "line " + std::to_string(line) + " declares a count " + excerpt(text) + " too large to be true");
  }
}

/// Braces must balance (Assimp's reader runs past the end of a block that never closes), and
/// the declared counts must fit the file.
void check_md5(const std::filesystem::path& path, std::istream& in, std::uintmax_t size) {
  long depth = 0, n = 0, open_line = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++n;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (c == '"') quoted = !quoted;
      if (quoted) continue;
      if (c == '/' && i + 1 < line.size() && line[i + 1] == '/') break;
      if (c == '{' && depth++ == 0) open_line = n;
      if (c == '}' && --depth < 0)
        fail(path, "not a valid MD5 file: line " + std::to_string(n) + " closes a '}' never opened");
    }
    std::istringstream words(line);
    std::string key, value;
    words >> key >> value;
    for (const char* counted : {"numJoints", "numMeshes", "numverts", "numtris", "numweights", "numFrames"})
      if (key == counted) check_count(path, key.substr(3), parse_count(path, value, n), size, n);
  }
  if (depth != 0)
    fail(path, "not a valid MD5 file: the block opened on line " + std::to_string(open_line) + " never closes");
}

/// The elements a PLY header declares must fit the file.
void check_ply(const std::filesystem::path& path, std::istream& in, std::uintmax_t size) {
  std::string line;
  long n = 0;
  while (std::getline(in, line)) {
    ++n;
    std::istringstream words(line);
    std::string key, name, count;
    words >> key;
    if (key == "end_header") return;
    if (key != "element") continue;
    words >> name >> count;
    check_count(path, "'" + name + "' elements", parse_count(path, count, n), size, n);
  }
}

/// The vertex and face counts of an OFF header ("[ST][C][N][4][n]OFF", then "nv nf ne", on the
/// same line or the next that is not a comment) must fit the file: Assimp's reader loops over
/// what it declares (353 535 235 358 vertices in a 309-byte file: minutes).
void check_off(const std::filesystem::path& path, std::istream& in, std::uintmax_t size) {
  std::string line;
  long n = 0;
  bool keyword = false;
  while (std::getline(in, line)) {
    ++n;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word) || word[0] == '#') continue;
    if (!keyword && word.ends_with("OFF")) {
      keyword = true;
      if (!(words >> word) || word[0] == '#') continue;
      if (word == "BINARY") return;  // counts in binary: the reader says what it can read
    }
    std::string faces;
    words >> faces;
    check_count(path, "vertices", parse_count(path, word, n), size, n);
    check_count(path, "faces", parse_count(path, faces, n), size, n);
    return;
  }
}

/// A GLB's header and chunk lengths must fit in the file: readers allocate what they declare
/// (a 4 GB JSON chunk took 30 s to refuse). Returns its JSON chunk ("" for a file that is not
/// binary glTF, or has none).
std::string check_glb(const std::filesystem::path& path, std::istream& in, std::uintmax_t size) {
  const auto u32 = [&](std::uint32_t& v) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
    v = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
    return true;
  };
  std::uint32_t magic = 0, version = 0, length = 0;
  if (!u32(magic) || !u32(version) || !u32(length)) fail(path, "not a valid .glb file: its header is cut short");
  if (magic != 0x46546c67u) return {};  // not binary glTF: the reader says what it is not
  if (length > size)
    fail(path, "not a valid .glb file: its header declares " + std::to_string(length) + " bytes but the file has " +
                   std::to_string(size) + " (truncated?)");
  std::string json;
  for (std::uintmax_t offset = 12; offset + 8 <= length;) {
    std::uint32_t chunk = 0, type = 0;
    if (!u32(chunk) || !u32(type)) fail(path, "not a valid .glb file: a chunk header is cut short");
    if (chunk > length - offset - 8)
      fail(path, "not a valid .glb file: the chunk at byte " + std::to_string(offset) + " declares " +
                     std::to_string(chunk) + " bytes, past the end of the file");
    if (offset == 12 && type == 0x4E4F534Au) {  // "JSON", always the first chunk
      json.resize(chunk);
      if (!in.read(json.data(), static_cast<std::streamsize>(chunk)))
        fail(path, "not a valid .glb file: its JSON chunk is cut short");
    }
    offset += 8 + chunk;
    in.seekg(static_cast<std::streamoff>(offset));
  }
  return json;
}

/// The extensions a glTF file may require: those Assimp's reader decodes (Debian's is built
/// with Draco) or whose absence changes no geometry (materials, lights, texture transforms).
const std::vector<std::string> kSupportedExtensions = {"KHR_draco_mesh_compression",
                                                       "KHR_lights_punctual",
                                                       "KHR_materials_clearcoat",
                                                       "KHR_materials_ior",
                                                       "KHR_materials_pbrSpecularGlossiness",
                                                       "KHR_materials_sheen",
                                                       "KHR_materials_transmission",
                                                       "KHR_materials_unlit",
                                                       "KHR_materials_volume",
                                                       "KHR_texture_basisu",
                                                       "KHR_texture_transform"};

/// What a glTF file's JSON says that Assimp's reader does not check: the extensions it requires
/// (one it cannot decode, such as EXT_meshopt_compression, makes it fail for a missing buffer
/// uri) and inverse bind matrices for every joint of a skin (glTF 2.0 §5.28; Assimp reads past
/// the accessor). JSON that does not parse is left to the reader to describe.
void check_gltf_json(const std::filesystem::path& path, const std::string& text) {
  const nlohmann::json gltf = nlohmann::json::parse(text, nullptr, false);
  if (!gltf.is_object()) return;
  if (const auto required = gltf.find("extensionsRequired"); required != gltf.end() && required->is_array()) {
    std::string unsupported;
    for (const auto& e : *required)
      if (e.is_string() && std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), e.get<std::string>()) ==
                               kSupportedExtensions.end())
        unsupported += (unsupported.empty() ? "" : ", ") + excerpt(e.get<std::string>());
    if (!unsupported.empty())
      fail(path,
           "it requires glTF extensions that cgamesh cannot read: " + unsupported + " (export the model without them)");
  }
  const auto skins = gltf.find("skins"), accessors = gltf.find("accessors");
  if (skins == gltf.end() || !skins->is_array()) return;
  for (std::size_t s = 0; s < skins->size(); ++s) {
    const auto& skin = (*skins)[s];
    if (!skin.is_object() || !skin.contains("joints") || !skin["joints"].is_array()) continue;
    const auto ibm = skin.find("inverseBindMatrices");
    if (ibm == skin.end() || !ibm->is_number_unsigned() || accessors == gltf.end() || !accessors->is_array() ||
        ibm->get<std::size_t>() >= accessors->size())
      continue;
    const auto& accessor = (*accessors)[ibm->get<std::size_t>()];
    const std::size_t joints = skin["joints"].size();
    if (!accessor.is_object() || !accessor.contains("count") || !accessor["count"].is_number_unsigned()) continue;
    const auto count = accessor["count"].get<std::uintmax_t>();
    if (count < joints) {
      const std::string name = skin.contains("name") && skin["name"].is_string()
                                   ? " '" + excerpt(skin["name"].get<std::string>()) + "'"
                                   : "";
      fail(path, "skin " + std::to_string(s) + name + " has " + std::to_string(joints) +
                     " joints but its inverseBindMatrices accessor holds " + std::to_string(count) +
                     " matrices (invalid glTF: one per joint)");
    }
  }
}

}  // namespace

void preflight(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".smd" && ext != ".md5mesh" && ext != ".md5anim" && ext != ".ply" && ext != ".glb" && ext != ".gltf" &&
      ext != ".off")
    return;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) fail(path, "the file cannot be read");
  if (ext == ".smd")
    check_smd(path, in);
  else if (ext == ".ply")
    check_ply(path, in, size);
  else if (ext == ".glb")
    check_gltf_json(path, check_glb(path, in, size));
  else if (ext == ".gltf")
    check_gltf_json(path, std::string(std::istreambuf_iterator<char>(in), {}));
  else if (ext == ".off")
    check_off(path, in, size);
  else
    check_md5(path, in, size);
}

}  // namespace cgamesh::io::detail
