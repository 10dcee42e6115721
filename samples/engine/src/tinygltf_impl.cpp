// The one translation unit that compiles tinygltf's implementation. stb_image's
// implementation comes from libstb.so (Debian), so it is not defined here;
// the engine never writes glTF, so the image writer is left out.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
