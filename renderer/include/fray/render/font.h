#pragma once
// A tiny embedded bitmap font (printable ASCII, 5x8 pixels per glyph, drawn
// for Fray) for labels in the viewport and on contact sheets. Text is drawn
// at integer scales so glyph pixels stay crisp and output is deterministic.
#include <cstdint>
#include <string_view>
#include <vector>

namespace fray::render::font {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 8;  // 7 rows above the baseline, 1 for descenders
inline constexpr int kAdvance = 6;      // glyph + 1 pixel spacing
inline constexpr int kLineHeight = 9;
inline constexpr int kFirstChar = 32;
inline constexpr int kLastChar = 126;
inline constexpr int kAtlasColumns = 16;
inline constexpr int kAtlasRows = 6;
inline constexpr int kAtlasWidth = kAtlasColumns * kAdvance;    // 96
inline constexpr int kAtlasHeight = kAtlasRows * kLineHeight;  // 54

// True when pixel (x, y) of the glyph is set; characters outside printable
// ASCII draw as '?'.
bool glyphPixel(char c, int x, int y);
// Cell of a character in the atlas (top-left pixel).
void atlasCell(char c, int& x, int& y);
// One byte per pixel (0 or 255), kAtlasWidth x kAtlasHeight, rows top to bottom.
std::vector<std::uint8_t> buildAtlas();
// Width and height in pixels of one line of text at a scale.
int textWidth(std::string_view text, int scale);
inline int textHeight(int scale) { return kGlyphHeight * scale; }

}  // namespace fray::render::font
