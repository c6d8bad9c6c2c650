#include "fray/setup/paint.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fray::setup {
namespace {

// 5 x 7 capitals and digits for the text stamp: one byte per row, top row
// first, bit 4 the leftmost cell.
struct Glyph {
    char c;
    std::array<std::uint8_t, 7> rows;
};
constexpr Glyph kGlyphs[] = {
    {'A', {0x0e, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11}}, {'B', {0x1e, 0x11, 0x11, 0x1e, 0x11, 0x11, 0x1e}},
    {'C', {0x0e, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0e}}, {'D', {0x1e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1e}},
    {'E', {0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f}}, {'F', {0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x10}},
    {'G', {0x0e, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0f}}, {'H', {0x11, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11}},
    {'I', {0x0e, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0c}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1f}},
    {'M', {0x11, 0x1b, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e}}, {'P', {0x1e, 0x11, 0x11, 0x1e, 0x10, 0x10, 0x10}},
    {'Q', {0x0e, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0d}}, {'R', {0x1e, 0x11, 0x11, 0x1e, 0x14, 0x12, 0x11}},
    {'S', {0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e}}, {'T', {0x1f, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0a, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0a}}, {'X', {0x11, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0a, 0x04, 0x04, 0x04}}, {'Z', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1f}},
    {'0', {0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e}}, {'1', {0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e}},
    {'2', {0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f}}, {'3', {0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e}},
    {'4', {0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02}}, {'5', {0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e}},
    {'6', {0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e}}, {'7', {0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e}}, {'9', {0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c}},
    {' ', {0, 0, 0, 0, 0, 0, 0}},
};

const Glyph* glyph(char c) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    for (const auto& g : kGlyphs) {
        if (g.c == c) return &g;
    }
    return nullptr;
}

// Pixel coordinates (fractional) of a floor point.
void toPixel(const FloorPaint& f, const Point& p, double& px, double& py) {
    px = (p.x - f.origin.x) / f.metresPerPixel;
    py = (p.z - f.origin.z) / f.metresPerPixel;
}

Point pixelCentre(const FloorPaint& f, int x, int y) {
    return {f.origin.x + (x + 0.5) * f.metresPerPixel, f.origin.z + (y + 0.5) * f.metresPerPixel};
}

double segmentDistance(const Point& p, const Point& a, const Point& b) {
    const double dx = b.x - a.x, dz = b.z - a.z, len2 = dx * dx + dz * dz;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.z - a.z) * dz) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.x - (a.x + dx * t), p.z - (a.z + dz * t));
}

// The letter cells of a text stamp: for each letter, its cell rectangles in metres.
struct Cell {
    Point lo, hi;
};
std::vector<std::vector<Cell>> letterCells(const FloorStroke& s) {
    std::vector<std::vector<Cell>> out;
    const double cell = s.letterHeight / 7.0;
    const Point corner = s.points.front();
    int column = 0;
    for (char c : s.text) {
        const Glyph* g = glyph(c);
        std::vector<Cell> cells;
        if (g) {
            for (int y = 0; y < 7; ++y) {
                for (int x = 0; x < 5; ++x) {
                    if (!((g->rows[static_cast<std::size_t>(y)] >> (4 - x)) & 1u)) continue;
                    const double x0 = corner.x + (column * 6 + x) * cell, z0 = corner.z + (6 - y) * cell;
                    cells.push_back({{x0, z0}, {x0 + cell, z0 + cell}});
                }
            }
        }
        out.push_back(std::move(cells));
        ++column;
    }
    return out;
}

}  // namespace

Result<std::vector<PixelChange>> applyStroke(FloorPaint& f, const FloorStroke& s) {
    if (f.empty() || f.painted.size() != static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height)) {
        return makeError("the setup has no floor bitmap to paint on");
    }
    if (s.points.empty()) return makeError("a stroke needs at least one point");
    for (const auto& p : s.points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.z)) return makeError("a stroke point is not a finite position");
    }
    if (s.startTime && (!std::isfinite(*s.startTime) || *s.startTime < 0 || *s.startTime > 3600)) {
        return makeError("a stroke's start time must be in [0, 3600] s");
    }
    std::vector<PixelChange> changes;
    auto set = [&](int x, int y, std::uint8_t v) {
        const int i = y * f.width + x;
        auto& px = f.painted[static_cast<std::size_t>(i)];
        if (px == v) return;
        changes.push_back({i, px, v});
        px = v;
    };
    switch (s.tool) {
    case FloorStroke::Tool::Brush:
    case FloorStroke::Tool::Eraser: {
        if (!(s.radius > 0) || s.radius > 100) return makeError("the brush radius must be in (0, 100] m");
        const std::uint8_t v = s.tool == FloorStroke::Tool::Brush ? 1 : 0;
        for (std::size_t k = 0; k < s.points.size(); ++k) {
            const Point a = s.points[k == 0 ? 0 : k - 1], b = s.points[k];
            double ax, ay, bx, by;
            toPixel(f, a, ax, ay);
            toPixel(f, b, bx, by);
            const double r = s.radius / f.metresPerPixel;
            const int x0 = std::max(0, static_cast<int>(std::floor(std::min(ax, bx) - r)));
            const int x1 = std::min(f.width - 1, static_cast<int>(std::ceil(std::max(ax, bx) + r)));
            const int y0 = std::max(0, static_cast<int>(std::floor(std::min(ay, by) - r)));
            const int y1 = std::min(f.height - 1, static_cast<int>(std::ceil(std::max(ay, by) + r)));
            for (int y = y0; y <= y1; ++y) {
                for (int x = x0; x <= x1; ++x) {
                    if (segmentDistance(pixelCentre(f, x, y), a, b) <= s.radius) set(x, y, v);
                }
            }
        }
        break;
    }
    case FloorStroke::Tool::Fill: {
        double px, py;
        toPixel(f, s.points.front(), px, py);
        if (!(px >= 0 && py >= 0 && px < f.width && py < f.height)) return makeError("the fill starts outside the floor bitmap");
        const int sx = static_cast<int>(px), sy = static_cast<int>(py);
        const std::uint8_t from = f.at(sx, sy), to = from ? 0 : 1;  // fills the unpainted region, or clears a painted one
        std::vector<std::pair<int, int>> stack{{sx, sy}};
        while (!stack.empty()) {
            const auto [x, y] = stack.back();
            stack.pop_back();
            if (x < 0 || y < 0 || x >= f.width || y >= f.height || f.at(x, y) != from) continue;
            set(x, y, to);
            stack.push_back({x + 1, y}), stack.push_back({x - 1, y}), stack.push_back({x, y + 1}), stack.push_back({x, y - 1});
        }
        break;
    }
    case FloorStroke::Tool::Text: {
        if (s.text.empty()) return makeError("the text stamp has no text");
        for (char c : s.text) {
            if (!glyph(c)) return makeError(std::string("the text stamp has no letter '") + c + "' (A-Z, 0-9 and space)");
        }
        if (!(s.letterHeight > 0) || s.letterHeight > 1000) return makeError("the letter height must be in (0, 1000] m");
        for (const auto& cells : letterCells(s)) {
            for (const auto& c : cells) {
                double x0, y0, x1, y1;
                toPixel(f, c.lo, x0, y0);
                toPixel(f, c.hi, x1, y1);
                // Pixels whose centre lies in the cell.
                for (int y = std::max(0, static_cast<int>(std::ceil(y0 - 0.5))); y <= std::min(f.height - 1, static_cast<int>(std::floor(y1 - 0.5))); ++y) {
                    for (int x = std::max(0, static_cast<int>(std::ceil(x0 - 0.5))); x <= std::min(f.width - 1, static_cast<int>(std::floor(x1 - 0.5))); ++x) {
                        if (x + 0.5 < x1 && y + 0.5 < y1) set(x, y, 1);
                    }
                }
            }
        }
        break;
    }
    }
    std::sort(changes.begin(), changes.end(), [](const PixelChange& a, const PixelChange& b) { return a.index < b.index; });
    return changes;
}

std::vector<DominoStartPoint> strokeStarts(const FloorPaint&, const FloorStroke& s) {
    std::vector<DominoStartPoint> out;
    if (!s.startTime || s.points.empty()) return out;
    if (s.tool == FloorStroke::Tool::Brush) {
        out.push_back({*s.startTime, s.points.front()});
    } else if (s.tool == FloorStroke::Tool::Text) {
        const auto letters = letterCells(s);
        double t = *s.startTime;
        for (const auto& cells : letters) {
            if (cells.empty()) continue;  // a space
            // The painted cell nearest the letter's centre (a chain must start on paint).
            Point lo = cells.front().lo, hi = cells.front().hi;
            for (const auto& c : cells) lo = {std::min(lo.x, c.lo.x), std::min(lo.z, c.lo.z)}, hi = {std::max(hi.x, c.hi.x), std::max(hi.z, c.hi.z)};
            const Point centre{(lo.x + hi.x) / 2, (lo.z + hi.z) / 2};
            const Cell* best = &cells.front();
            double bestD = 1e300;
            for (const auto& c : cells) {
                const double d = std::hypot((c.lo.x + c.hi.x) / 2 - centre.x, (c.lo.z + c.hi.z) / 2 - centre.z);
                if (d < bestD) bestD = d, best = &c;
            }
            out.push_back({t, {(best->lo.x + best->hi.x) / 2, (best->lo.z + best->hi.z) / 2}});
            t += s.letterInterval;
        }
    }
    return out;
}

PixelRect changedRect(const FloorPaint& f, const std::vector<PixelChange>& changes) {
    if (changes.empty() || f.width <= 0) return {};
    int x0 = f.width, y0 = f.height, x1 = -1, y1 = -1;
    for (const auto& c : changes) {
        const int x = c.index % f.width, y = c.index / f.width;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

void rectMetres(const FloorPaint& f, const PixelRect& r, Point& lo, Point& hi) {
    lo = {f.origin.x + r.x * f.metresPerPixel, f.origin.z + r.y * f.metresPerPixel};
    hi = {f.origin.x + (r.x + r.width) * f.metresPerPixel, f.origin.z + (r.y + r.height) * f.metresPerPixel};
}

Result<FloorPaint> floorFromRgba(int width, int height, const std::uint8_t* rgba, double metresPerPixel, Point origin,
                                 const std::string& what) {
    if (width < 1 || height < 1) return makeError(what + ": the image is empty");
    if (width > kMaxFloorPixels || height > kMaxFloorPixels) {
        return makeError(what + ": " + std::to_string(width) + " x " + std::to_string(height) + " pixels is larger than " +
                         std::to_string(kMaxFloorPixels) + " a side");
    }
    FloorPaint f;
    f.width = width, f.height = height, f.metresPerPixel = metresPerPixel, f.origin = origin;
    f.painted.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* px = rgba + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
            if (px[3] < 128) continue;
            const int luma = (299 * px[0] + 587 * px[1] + 114 * px[2]) / 1000;
            if (luma > 64 && luma < 192) {
                char colour[8];
                std::snprintf(colour, sizeof colour, "#%02x%02x%02x", px[0], px[1], px[2]);
                return makeError(what + ": not a two-colour image: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " +
                                 colour + "; paint the area in black on white (or on transparent)");
            }
            if (luma <= 64) f.painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = 1;
        }
    }
    return f;
}

}  // namespace fray::setup
