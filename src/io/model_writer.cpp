#include "cgamesh/io/model_writer.hpp"

#include <algorithm>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/mesh_writer.hpp"

namespace cgamesh::io {

bool is_rigged_format(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return std::find(kRiggedExtensions.begin(), kRiggedExtensions.end(), ext) != kRiggedExtensions.end();
}

std::vector<EncodedFile> encode_model(const anim::RiggedModel& model, const std::filesystem::path& out,
                                      const std::function<mesh::WorldSurface()>& surface, std::vector<std::string>* warnings) {
  if (is_rigged_format(out)) return encode_gltf(model, out, {}, warnings);
  const std::string ext = lower_extension(out);
  if (std::find(kModelExtensions.begin(), kModelExtensions.end(), ext) == kModelExtensions.end())
    throw InvalidInputError("'" + out.string() + "': a model is written as .glb, .gltf, .obj or .ply (the extension chooses)");
  const mesh::WorldSurface s = surface();
  return {encode_mesh(model.meshes, s.positions, out, s.normals)};
}

std::vector<std::string> write_model(const anim::RiggedModel& model, const std::filesystem::path& out,
                                     const std::function<mesh::WorldSurface()>& surface) {
  std::vector<std::string> warnings;
  write_files_atomically(encode_model(model, out, surface, &warnings));
  return warnings;
}

}  // namespace cgamesh::io
