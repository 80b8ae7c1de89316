// tinygltf's implementation, compiled here rather than taken from Debian's libtinygltf.so, with
// the configuration every user of the header gets from CMakeLists.txt: images never decoded
// (TINYGLTF_NO_*IMAGE) and the namespace renamed to cgamesh_tinygltf, because libdraco (an
// Assimp dependency) exports its own tinygltf build under the same symbol names.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
