// tinygltf's implementation, compiled into the fuzz build instead of linking Debian's shared
// library: instrumented, the fuzzer can steer through tinygltf's JSON and GLB parsing (where
// most of a hostile file is rejected), and ASan and UBSan check that code too. Images are never
// decoded (dynrt drops them), so stb is left out through the target's definitions.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
