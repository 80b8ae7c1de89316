#include "preflight.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "cgamesh/errors.hpp"

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
    fail(path, "line " + std::to_string(line) + " declares a count '" + text + "' that is not a whole number");
  try {
    return std::stoull(text);
  } catch (const std::out_of_range&) {
    fail(path, "line " + std::to_string(line) + " declares a count " + text + " too large to be true");
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
/// (a 4 GB JSON chunk took 30 s to refuse).
void check_glb(const std::filesystem::path& path, std::istream& in, std::uintmax_t size) {
  const auto u32 = [&](std::uint32_t& v) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
    v = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
    return true;
  };
  std::uint32_t magic = 0, version = 0, length = 0;
  if (!u32(magic) || !u32(version) || !u32(length)) fail(path, "not a valid .glb file: its header is cut short");
  if (magic != 0x46546c67u) return;  // not binary glTF: the reader says what it is not
  if (length > size)
    fail(path, "not a valid .glb file: its header declares " + std::to_string(length) + " bytes but the file has " +
                   std::to_string(size) + " (truncated?)");
  for (std::uintmax_t offset = 12; offset + 8 <= length;) {
    std::uint32_t chunk = 0, type = 0;
    if (!u32(chunk) || !u32(type)) fail(path, "not a valid .glb file: a chunk header is cut short");
    if (chunk > length - offset - 8)
      fail(path, "not a valid .glb file: the chunk at byte " + std::to_string(offset) + " declares " +
                     std::to_string(chunk) + " bytes, past the end of the file");
    offset += 8 + chunk;
    in.seekg(static_cast<std::streamoff>(offset));
  }
}

}  // namespace

void preflight(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".smd" && ext != ".md5mesh" && ext != ".md5anim" && ext != ".ply" && ext != ".glb" && ext != ".off")
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
    check_glb(path, in, size);
  else if (ext == ".off")
    check_off(path, in, size);
  else
    check_md5(path, in, size);
}

}  // namespace cgamesh::io::detail
