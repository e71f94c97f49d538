// tinygltf's implementation, for the web build only: natively it comes from Debian's
// libtinygltf, which has no WebAssembly build. Images stay encoded (the importer sets its
// own image loader), so stb_image is left out (TINYGLTF_NO_STB_IMAGE, cmake/MarionetteWeb.cmake).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
