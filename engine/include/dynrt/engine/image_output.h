#pragma once
// Writing rendered frames to image files through OpenImageIO.

#include "dynrt/engine/display_transform.h"
#include "dynrt/engine/renderer.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <span>
#include <vector>

namespace dynrt {

/// Auxiliary per-pixel outputs written next to the image for pixel-by-pixel comparison.
/// cost: each pixel's camera-ray work in the frame's trees (dynrt/engine/pixel_cost.h), which
/// needs TraceSettings::pixel_cost.
enum class Aov { depth, object, prim, normal, cost };

/// Its name in --aov lists and file names ("depth", ..., "cost").
const char* aov_name(Aov aov);

/// Parses "depth,object,prim,normal,cost" (any subset, no repeats; empty string = none).
/// Throws std::invalid_argument naming an unknown or repeated entry.
std::vector<Aov> parse_aov_list(const std::string& list);

/// Writes the colour image; the format follows the extension (.png, .exr, .jpg, .tif, ...).
/// Float formats (.exr, .hdr, .pfm) get linear values; all others get `display`'s exposure and
/// tone curve (none by default), then sRGB-encoded 8-bit values clamped to [0, 1]. Throws
/// std::runtime_error naming the file on failure.
void write_image(const std::filesystem::path& path, const RenderedFrame& frame,
                 const DisplayTransform& display = {});

/// The bytes write_image writes to an 8-bit file: `frame`'s colours through `display`, then
/// 8-bit sRGB, RGB interleaved, rows from the top. What a window shows of the frame.
std::vector<std::uint8_t> display_rgb8(const RenderedFrame& frame, const DisplayTransform& display = {});

/// Writes 8-bit RGB `rgb` (width x height, rows from the top) to an 8-bit image file such as a
/// PNG, as write_image writes its bytes. Throws std::runtime_error naming the file on failure.
void write_image_rgb8(const std::filesystem::path& path, int width, int height, std::span<const std::uint8_t> rgb);

/// Throws std::invalid_argument when `path` cannot be written as an image: unknown format
/// extension or missing parent folder. Lets callers fail before a long render, not after.
void check_image_path(const std::filesystem::path& path);

/// Path of one AOV next to `image`: "<dir>/<image stem>.<aov>.exr".
std::filesystem::path aov_path(const std::filesystem::path& image, Aov aov);

/// Writes float EXR images: depth (1 channel, +inf on a miss), object and prim (1 channel,
/// -1 on a miss; exact up to 2^24), normal (3 channels, 0 on a miss), cost (2 channels named
/// "nodes" and "triangles"). Throws std::invalid_argument for a cost AOV of a frame traced
/// without TraceSettings::pixel_cost.
void write_aov(const std::filesystem::path& image, Aov aov, const RenderedFrame& frame);

}  // namespace dynrt
