#pragma once
// A scene texture's texels, decoded once: OpenImageIO reads and decodes the file or the
// embedded bytes (PNG, JPEG, PPM, BMP, EXR...); texels given as an array are checked and
// taken as they are. The MIP levels are made from the result (mip_pyramid.h).

#include "dynrt/scene/scene.h"

#include <string>

namespace dynrt::textures {

/// The decoded texels of `texture`, or an empty array with `problem` saying why it cannot be
/// read (one line: "no such file", a decoder's reason, "truncated", "too large"). 8-bit images
/// stay 8-bit; deeper ones (16-bit, half, float) become float. At most four channels are
/// kept; colours are as stored (alpha not multiplied in: glTF's are unassociated). A float
/// texel that is not finite becomes 0.
TexelArray decode_texture(const Texture& texture, std::string& problem);

}  // namespace dynrt::textures
