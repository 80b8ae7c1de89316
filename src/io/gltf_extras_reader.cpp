#include "gltf_extras_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>

#include <tiny_gltf.h>

#include "cgamesh/errors.hpp"

#include "excerpt.hpp"
#include "cgamesh/io/file_extension.hpp"

namespace cgamesh::io::detail {
namespace {

using anim::Channel;
using anim::ChannelPath;
using anim::Interpolation;

/// Images are irrelevant to animation: accept them undecoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

/// One component of element i of an accessor, as a double (normalised integers per glTF §3.11).
class AccessorView {
 public:
  AccessorView(const tinygltf::Model& model, int index, const std::string& what) {
    if (index < 0 || index >= static_cast<int>(model.accessors.size())) throw FileError(what + ": no such accessor");
    const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse || a.bufferView < 0) throw FileError(what + ": sparse or empty accessors are not supported");
    const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
    const tinygltf::Buffer& buffer = model.buffers.at(static_cast<std::size_t>(view.buffer));
    components_ = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    size_ = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (components_ <= 0 || size_ <= 0) throw FileError(what + ": invalid accessor type");
    type_ = a.componentType;
    normalized_ = a.normalized;
    count_ = a.count;
    const int stride = a.ByteStride(view);
    stride_ = stride > 0 ? static_cast<std::size_t>(stride) : static_cast<std::size_t>(components_ * size_);
    offset_ = view.byteOffset + a.byteOffset;
    const std::size_t needed =
        count_ == 0 ? 0 : offset_ + (count_ - 1) * stride_ + static_cast<std::size_t>(components_ * size_);
    if (needed > buffer.data.size() || view.byteOffset + view.byteLength > buffer.data.size())
      throw FileError(what + ": accessor runs past the end of its buffer");
    data_ = buffer.data.data();
  }

  [[nodiscard]] std::size_t count() const noexcept { return count_; }
  [[nodiscard]] int components() const noexcept { return components_; }

  [[nodiscard]] double get(std::size_t i, int c) const {
    const unsigned char* p = data_ + offset_ + i * stride_ + static_cast<std::size_t>(c * size_);
    switch (type_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return read<float>(p, 1.0);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return std::max(read<std::int8_t>(p, 127.0), -1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return read<std::uint8_t>(p, 255.0);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return std::max(read<std::int16_t>(p, 32767.0), -1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return read<std::uint16_t>(p, 65535.0);
      default:
        throw FileError("animation accessor of unsupported component type " + std::to_string(type_));
    }
  }

 private:
  template <class T>
  [[nodiscard]] double read(const unsigned char* p, double scale) const {
    T v;
    std::memcpy(&v, p, sizeof v);
    return normalized_ ? static_cast<double>(v) / scale : static_cast<double>(v);
  }

  const unsigned char* data_ = nullptr;
  std::size_t offset_ = 0, stride_ = 0, count_ = 0;
  int components_ = 0, size_ = 0, type_ = 0;
  bool normalized_ = false;
};

std::optional<ChannelPath> channel_path(const std::string& path) {
  if (path == "translation") return ChannelPath::translation;
  if (path == "rotation") return ChannelPath::rotation;
  if (path == "scale") return ChannelPath::scale;
  if (path == "weights") return ChannelPath::weights;
  return std::nullopt;  // an extension's path
}

Interpolation interpolation(const std::string& name, const std::string& what) {
  if (name.empty() || name == "LINEAR") return Interpolation::linear;
  if (name == "STEP") return Interpolation::step;
  if (name == "CUBICSPLINE") return Interpolation::cubic_spline;
  throw FileError(what + ": unknown interpolation '" + name + "'");
}

/// Reads one sampler into `ch` (joint and path already set). Keys whose time does not increase
/// are dropped, as the Assimp path does.
void read_sampler(const tinygltf::Model& model, const tinygltf::AnimationSampler& sampler, Channel& ch,
                  const std::string& what) {
  ch.interpolation = interpolation(sampler.interpolation, what);
  const AccessorView input(model, sampler.input, what + " input");
  const AccessorView output(model, sampler.output, what + " output");
  const std::size_t blocks = ch.interpolation == Interpolation::cubic_spline ? 3 : 1;
  // Weights: a SCALAR output of #targets values per key (and per block).
  if (ch.path == ChannelPath::weights && output.components() == 1 && input.count() > 0)
    ch.weight_count = static_cast<int>(output.count() / (blocks * input.count()));
  const int n = ch.components();
  const bool matches =
      ch.path == ChannelPath::weights
          ? n > 0 && output.components() == 1 && output.count() == blocks * input.count() * static_cast<std::size_t>(n)
          : output.components() == n && output.count() == blocks * input.count();
  if (input.components() != 1 || !matches) throw FileError(what + ": sampler input and output do not match");
  // A weights key is n scalar elements; a TRS key one element of n components.
  const std::size_t per_element = ch.path == ChannelPath::weights ? static_cast<std::size_t>(n) : 1;
  for (std::size_t k = 0; k < input.count(); ++k) {
    const double t = input.get(k, 0);
    if (!std::isfinite(t)) throw FileError(what + " has a NaN key time");
    if (!ch.times.empty() && t <= ch.times.back()) continue;
    ch.times.push_back(t);
    for (std::size_t b = 0; b < blocks; ++b)
      for (int c = 0; c < n; ++c) {
        const double v = per_element == 1 ? output.get(k * blocks + b, c)
                                          : output.get((k * blocks + b) * per_element + static_cast<std::size_t>(c), 0);
        if (!std::isfinite(v)) throw FileError(what + " has NaN or infinite key values");
        ch.values.push_back(v);
      }
  }
}

/// The clips of the file, channels bound to `skeleton` joints by node name (or Assimp's
/// "nodes[i]" for unnamed nodes), with times, values and interpolation as the file stores them
/// (cubic splines keep their in/out tangents). A morph-weights channel is kept when the meshes on
/// its node have as many targets as it has weights.
std::vector<anim::Clip> read_gltf_clips(const tinygltf::Model& model, const anim::Skeleton& skeleton,
                                        std::span<const mesh::Mesh> meshes, std::vector<std::string>& warnings) {
  std::vector<anim::Clip> clips;
  for (std::size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& in = model.animations[a];
    anim::Clip clip;
    clip.name = in.name.empty() ? "clip" + std::to_string(a) : in.name;
    for (std::size_t c = 0; c < in.channels.size(); ++c) {
      const tinygltf::AnimationChannel& target = in.channels[c];
      const std::string what = "animation '" + clip.name + "' channel " + std::to_string(c);
      const auto path_kind = channel_path(target.target_path);
      if (!path_kind) continue;
      if (target.target_node < 0 || target.target_node >= static_cast<int>(model.nodes.size()))
        throw FileError(what + " targets no node");
      const std::size_t node = static_cast<std::size_t>(target.target_node);
      const std::string name =
          model.nodes[node].name.empty() ? "nodes[" + std::to_string(node) + "]" : model.nodes[node].name;
      Channel ch;
      ch.joint = skeleton.find(name);
      ch.path = *path_kind;
      if (ch.joint < 0) {
        warnings.push_back(what + " animates node '" + name + "', which is not in the skeleton; ignored");
        continue;
      }
      if (target.sampler < 0 || target.sampler >= static_cast<int>(in.samplers.size()))
        throw FileError(what + " has no sampler");
      read_sampler(model, in.samplers[static_cast<std::size_t>(target.sampler)], ch, what);
      if (ch.times.empty()) continue;
      if (ch.path == ChannelPath::weights && std::none_of(meshes.begin(), meshes.end(), [&](const mesh::Mesh& m) {
            return m.node == ch.joint && m.morph_targets.size() == static_cast<std::size_t>(ch.weight_count);
          })) {
        warnings.push_back(what + " animates " + std::to_string(ch.weight_count) + " morph weights of node '" + name +
                           "', which has no mesh with that many morph targets; ignored");
        continue;
      }
      clip.duration = std::max(clip.duration, ch.times.back());
      clip.channels.push_back(std::move(ch));
    }
    clips.push_back(std::move(clip));
  }
  return clips;
}

/// Mesh::generated of `m` from a primitive that has _CGAMESH_GENERATED and exactly m's
/// positions (left empty when none has).
void read_generated(const tinygltf::Model& file, mesh::Mesh& m) {
  const auto nv = static_cast<std::size_t>(m.vertex_count());
  for (const tinygltf::Mesh& gm : file.meshes)
    for (const tinygltf::Primitive& p : gm.primitives) {
      const auto flag = p.attributes.find(kGeneratedAttribute), position = p.attributes.find("POSITION");
      if (flag == p.attributes.end() || position == p.attributes.end()) continue;
      const AccessorView flags(file, flag->second, kGeneratedAttribute), xyz(file, position->second, "POSITION");
      if (flags.count() != nv || xyz.count() != nv || flags.components() != 1 || xyz.components() != 3) continue;
      bool same = true;
      for (std::size_t v = 0; v < nv && same; ++v)
        for (int c = 0; c < 3; ++c)
          same = same && static_cast<float>(xyz.get(v, c)) == m.positions(static_cast<Eigen::Index>(v), c);
      if (!same) continue;
      m.generated.resize(static_cast<Eigen::Index>(nv));
      for (std::size_t v = 0; v < nv; ++v) m.generated[static_cast<Eigen::Index>(v)] = flags.get(v, 0) > 0.5 ? 1 : 0;
      return;
    }
}

/// A node's weights override its mesh's (glTF 2.0 §3.7.2.2), which Assimp reads alone.
void read_node_weights(const tinygltf::Model& file, anim::RiggedModel& model) {
  for (std::size_t n = 0; n < file.nodes.size(); ++n) {
    const tinygltf::Node& node = file.nodes[n];
    if (node.weights.empty()) continue;
    const int joint = model.skeleton.find(node.name.empty() ? "nodes[" + std::to_string(n) + "]" : node.name);
    for (mesh::Mesh& m : model.meshes)
      if (m.node == joint && joint >= 0 && m.morph_targets.size() == node.weights.size())
        m.morph_weights.assign(node.weights.begin(), node.weights.end());
  }
}

}  // namespace

bool is_gltf(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".gltf" || ext == ".glb";
}

void read_gltf_extras(const std::filesystem::path& path, anim::RiggedModel& model) {
  tinygltf::TinyGLTF reader;
  reader.SetImageLoader(&skip_image, nullptr);
  tinygltf::Model file;
  std::string err, warn;
  const bool ok = lower_extension(path) == ".glb" ? reader.LoadBinaryFromFile(&file, &err, &warn, path.string())
                                                  : reader.LoadASCIIFromFile(&file, &err, &warn, path.string());
  if (!ok) {
    // Assimp read the file (glTF 1.0, say, which tinygltf does not): its LINEAR keys stand.
    while (!err.empty() && err.back() == '\n') err.pop_back();
    model.warnings.push_back("the animations' interpolation could not be read (" + excerpt(err) +
                             "); keys load as LINEAR");
    return;
  }
  std::vector<std::string> warnings;
  std::vector<anim::Clip> clips = read_gltf_clips(file, model.skeleton, model.meshes, warnings);
  if (clips.size() != model.clips.size())
    warnings.push_back("the glTF animations did not match Assimp's; keys load as LINEAR");
  else
    model.clips = std::move(clips);
  for (mesh::Mesh& m : model.meshes) read_generated(file, m);
  read_node_weights(file, model);
  model.warnings.insert(model.warnings.end(), warnings.begin(), warnings.end());
}

}  // namespace cgamesh::io::detail
