#pragma once
// Reading a .glb into tinygltf's model and writing it back: tests craft files (a mirroring
// node, a broken key) from shipped models.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

namespace cgamesh_test {

/// The file as tinygltf reads it, images left undecoded in their buffer views.
inline tinygltf::Model read_glb(const std::filesystem::path& path) {
  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                         void*) { return true; },
                      nullptr);
  tinygltf::Model m;
  std::string err, warn;
  EXPECT_TRUE(gltf.LoadBinaryFromFile(&m, &err, &warn, path.string())) << path << ": " << err;
  return m;
}

/// Writes `m` as a .glb at `path` and returns `path`.
inline std::filesystem::path write_glb(tinygltf::Model m, const std::filesystem::path& path) {
  tinygltf::TinyGLTF gltf;
  EXPECT_TRUE(gltf.WriteGltfSceneToFile(&m, path.string(), true, true, true, true)) << path;
  return path;
}

}  // namespace cgamesh_test
