#include "cgamesh/io/mesh_writer.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <limits>
#include <string>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

#include "cgamesh/io/file_extension.hpp"

namespace cgamesh::io {
namespace {

[[noreturn]] void invalid(const std::string& message) { throw InvalidInputError("write_mesh: " + message); }

std::string label(const mesh::Mesh& m, std::size_t index) {
  return "mesh " + std::to_string(index) + (m.name.empty() ? std::string() : " ('" + m.name + "')");
}

using Rows3 = std::span<const mesh::RowMatrixXf<3>>;

/// Whether mesh i has normals to write (checked: 0 or #V rows).
bool has_normals(std::span<const mesh::Mesh> meshes, Rows3 normals, std::size_t i) {
  return !normals.empty() && meshes[i].vertex_count() > 0 && normals[i].rows() == meshes[i].vertex_count();
}

/// Checks the inputs; returns the total vertex count.
std::int64_t check(std::span<const mesh::Mesh> meshes, Rows3 positions, Rows3 normals) {
  if (meshes.empty()) invalid("no meshes to write");
  if (positions.size() != meshes.size())
    invalid(std::to_string(positions.size()) + " position sets for " + std::to_string(meshes.size()) + " meshes");
  if (!normals.empty() && normals.size() != meshes.size())
    invalid(std::to_string(normals.size()) + " normal sets for " + std::to_string(meshes.size()) + " meshes");
  std::int64_t total = 0;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const mesh::Mesh& m = meshes[i];
    const Eigen::Index nv = m.vertex_count();
    if (positions[i].rows() != nv)
      invalid(label(m, i) + " has " + std::to_string(nv) + " vertices but " + std::to_string(positions[i].rows()) +
              " posed positions");
    if (!positions[i].allFinite()) invalid(label(m, i) + " has NaN or infinite posed positions");
    if (!normals.empty()) {
      if (normals[i].rows() != 0 && normals[i].rows() != nv)
        invalid(label(m, i) + " has " + std::to_string(normals[i].rows()) + " posed normals for " + std::to_string(nv) +
                " vertices");
      if (!normals[i].allFinite()) invalid(label(m, i) + " has NaN or infinite posed normals");
    }
    if (m.uvs.rows() != 0 && m.uvs.rows() != nv)
      invalid(label(m, i) + " has " + std::to_string(m.uvs.rows()) + " texture coordinates for " + std::to_string(nv) +
              " vertices");
    if (!m.uvs.allFinite()) invalid(label(m, i) + " has NaN or infinite texture coordinates");
    if (m.faces.size() > 0 && (m.faces.minCoeff() < 0 || m.faces.maxCoeff() >= nv))
      invalid(label(m, i) + " has a face index outside [0, " + std::to_string(nv) + ")");
    total += nv;
    if (total > std::numeric_limits<std::int32_t>::max()) invalid("more than 2^31 - 1 vertices in total");
  }
  return total;
}

void append_float(std::string& s, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 9);
  s.append(buf, r.ptr);
}

void append_int(std::string& s, std::int64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

std::string obj_name(const mesh::Mesh& m, std::size_t index) {
  if (m.name.empty()) return "mesh" + std::to_string(index);
  std::string name = m.name;
  for (char& c : name)
    if (std::isspace(static_cast<unsigned char>(c)) || std::iscntrl(static_cast<unsigned char>(c))) c = '_';
  return name;
}

/// `tag x y z` lines, one per row of `rows`.
void append_rows(std::string& s, const char* tag, const mesh::RowMatrixXf<3>& rows) {
  for (Eigen::Index v = 0; v < rows.rows(); ++v) {
    s += tag;
    for (int c = 0; c < 3; ++c) {
      s += ' ';
      append_float(s, rows(v, c));
    }
    s += '\n';
  }
}

std::string make_obj(std::span<const mesh::Mesh> meshes, Rows3 positions, Rows3 normals) {
  std::string s = "# cgamesh posed mesh\n";
  std::int64_t v_base = 1, vt_base = 1, vn_base = 1;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const mesh::Mesh& m = meshes[i];
    const auto& p = positions[i];
    const bool uv = m.uvs.rows() == m.vertex_count() && m.vertex_count() > 0;
    const bool n = has_normals(meshes, normals, i);
    s += "o " + obj_name(m, i) + "\n";
    append_rows(s, "v", p);
    if (uv)
      for (Eigen::Index v = 0; v < m.uvs.rows(); ++v) {
        s += "vt ";
        append_float(s, m.uvs(v, 0));
        s += ' ';
        append_float(s, m.uvs(v, 1));
        s += '\n';
      }
    if (n) append_rows(s, "vn", normals[i]);
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      s += "f";
      for (int c = 0; c < 3; ++c) {
        s += ' ';
        append_int(s, v_base + m.faces(f, c));
        if (uv || n) s += '/';
        if (uv) append_int(s, vt_base + m.faces(f, c));
        if (n) {
          s += '/';
          append_int(s, vn_base + m.faces(f, c));
        }
      }
      s += '\n';
    }
    v_base += p.rows();
    if (uv) vt_base += m.uvs.rows();
    if (n) vn_base += normals[i].rows();
  }
  return s;
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) s += static_cast<char>((v >> (8 * b)) & 0xff);
}

std::string make_ply(std::span<const mesh::Mesh> meshes, Rows3 positions, Rows3 normals, std::int64_t vertices) {
  std::int64_t faces = 0;
  for (const mesh::Mesh& m : meshes) faces += m.face_count();
  // One vertex element for all meshes: normals when every mesh that has vertices has them.
  bool n = !normals.empty() && vertices > 0;
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (meshes[i].vertex_count() > 0 && !has_normals(meshes, normals, i)) n = false;
  std::string s = "ply\nformat binary_little_endian 1.0\ncomment generated by cgamesh\nelement vertex ";
  append_int(s, vertices);
  s += "\nproperty float x\nproperty float y\nproperty float z\n";
  if (n) s += "property float nx\nproperty float ny\nproperty float nz\n";
  s += "element face ";
  append_int(s, faces);
  s += "\nproperty list uchar int vertex_indices\nend_header\n";
  s.reserve(s.size() + static_cast<std::size_t>((n ? 24 : 12) * vertices + 13 * faces));
  for (std::size_t i = 0; i < meshes.size(); ++i)
    for (Eigen::Index v = 0; v < positions[i].rows(); ++v) {
      for (int c = 0; c < 3; ++c) put_u32(s, std::bit_cast<std::uint32_t>(positions[i](v, c)));
      if (n)
        for (int c = 0; c < 3; ++c) put_u32(s, std::bit_cast<std::uint32_t>(normals[i](v, c)));
    }
  std::int64_t base = 0;
  for (const mesh::Mesh& m : meshes) {
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      s += static_cast<char>(3);
      for (int c = 0; c < 3; ++c) put_u32(s, static_cast<std::uint32_t>(base + m.faces(f, c)));
    }
    base += m.vertex_count();
  }
  return s;
}

}  // namespace

EncodedFile encode_mesh(std::span<const mesh::Mesh> meshes, Rows3 positions, const std::filesystem::path& out,
                        Rows3 normals) {
  const std::string ext = lower_extension(out);
  if (ext != ".obj" && ext != ".ply")
    invalid("unknown extension '" + out.extension().string() + "' of '" + out.string() + "' (expected .obj or .ply)");
  const std::int64_t vertices = check(meshes, positions, normals);
  return {out, ext == ".obj" ? make_obj(meshes, positions, normals) : make_ply(meshes, positions, normals, vertices)};
}

void write_mesh(std::span<const mesh::Mesh> meshes, Rows3 positions, const std::filesystem::path& out, Rows3 normals) {
  const EncodedFile file = encode_mesh(meshes, positions, out, normals);
  write_file_atomically(file.path, file.bytes);
}

}  // namespace cgamesh::io
