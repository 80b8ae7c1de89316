// tinygltf's implementation, compiled here rather than taken from Debian's libtinygltf.so: that
// library was built with other configuration macros, so its TinyGLTF class layout differs from the
// header we compile against (loading through it crashed). Images are never decoded
// by cgamesh: CMakeLists.txt sets the TINYGLTF_NO_*IMAGE macros for every user of the header.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
