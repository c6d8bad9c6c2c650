#pragma once
// RGBA8 images, PNG files (libpng) and the tolerance comparison the golden
// image tests use.
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "fray/core/result.h"

namespace fray::render {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4, rows top to bottom

    void resize(int w, int h);  // keeps capacity; contents unspecified
    bool empty() const { return width <= 0 || height <= 0; }
    std::uint8_t* pixel(int x, int y) { return rgba.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4; }
    const std::uint8_t* pixel(int x, int y) const {
        return rgba.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
    }
};

// Writes an 8-bit RGBA PNG atomically (temporary file + rename). Errors name the file.
Status writePng(const std::filesystem::path& path, const Image& image);
// Reads any 8-bit or 16-bit PNG as RGBA8. Errors name the file and the problem.
Result<Image> readPng(const std::filesystem::path& path);

// Draws text with the embedded bitmap font (top-left corner at x, y), over a
// dark box when `box` is set (captions on contact sheets).
void drawText(Image& image, int x, int y, std::string_view text, int scale, const std::uint8_t rgba[4], bool box);

// Copies src into dst with its top-left corner at (x, y); clipped to dst.
void blit(const Image& src, Image& dst, int x, int y);

struct ImageDiff {
    int differing = 0;     // pixels where some channel differs by more than the threshold
    int total = 0;
    int maxDelta = 0;      // largest channel difference
    int minX = 0, minY = 0, maxX = -1, maxY = -1;  // box around the differing pixels (empty: maxX < minX)
    bool sizeMismatch = false;
    double fraction() const { return total > 0 ? static_cast<double>(differing) / total : 1.0; }
};

// Pixel-wise comparison: a pixel differs when any channel differs by more than threshold levels.
ImageDiff compareImages(const Image& a, const Image& b, int threshold);
// A visual difference: grey copy of a with the differing pixels in red.
Image diffImage(const Image& a, const Image& b, int threshold);

// Colour statistics: number of distinct colours (capped at cap) and the
// standard deviation of luminance, for "not blank, not uniform" checks.
struct ImageStats {
    int distinctColors = 0;
    double lumaStdDev = 0.0;
    double meanLuma = 0.0;
};
ImageStats imageStats(const Image& image, int cap = 4096);

}  // namespace fray::render
