#pragma once
// Painting the floor bitmap of a setup (issue 23): brush, eraser, flood fill
// and a text stamp (the thesis' falling letters), each one stroke in floor
// metres. applyStroke changes the bitmap and returns exactly the pixels it
// changed, so an undo step can hold them and a live re-plan can tell which
// area moved. Plain C++ (the editor's tools and the CLI share it).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/setup/scene_setup.h"

namespace fray::setup {

struct FloorStroke {
    enum class Tool { Brush, Eraser, Fill, Text };
    Tool tool = Tool::Brush;
    std::vector<Point> points;  // Brush/Eraser: the dragged polyline; Fill: the seed; Text: the first letter's lower-left corner
    double radius = 0.3;        // Brush/Eraser: m
    std::string text;           // Text: A-Z, 0-9, space (lower case is drawn upper case)
    double letterHeight = 2.0;  // Text: m (letters are 5 x 7 cells)
    // Domino: the chain starts here at this time (s). Brush: at the stroke's
    // first point; Text: each letter starts at its centre, `letterInterval` s
    // after the one before.
    std::optional<double> startTime;
    double letterInterval = 1.0;
};

struct PixelChange {
    int index = 0;  // y * width + x
    std::uint8_t before = 0, after = 0;
    friend bool operator==(const PixelChange&, const PixelChange&) = default;
};

struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0;
    bool empty() const { return width <= 0 || height <= 0; }
    friend bool operator==(const PixelRect&, const PixelRect&) = default;
};

// Paints `stroke` into `floor`; the changed pixels in ascending index order.
// Errors (nothing changed): no points, a radius that is not positive, text
// with characters the stamp lacks, a fill seed outside the bitmap.
Result<std::vector<PixelChange>> applyStroke(FloorPaint& floor, const FloorStroke& stroke);
// The domino starts a stroke adds (see FloorStroke::startTime).
std::vector<DominoStartPoint> strokeStarts(const FloorPaint& floor, const FloorStroke& stroke);
// Bounding box of changed pixels (empty for none) and the same in floor metres.
PixelRect changedRect(const FloorPaint& floor, const std::vector<PixelChange>& changes);
void rectMetres(const FloorPaint& floor, const PixelRect& rect, Point& lo, Point& hi);

// A floor from RGBA pixels (row-major, 4 bytes a pixel, row 0 first): dark
// pixels (luma <= 64) are painted, light (>= 192) or transparent (alpha <
// 128) ones are not; anything in between is refused (it is not a mask).
// `what` names the source in errors.
Result<FloorPaint> floorFromRgba(int width, int height, const std::uint8_t* rgba, double metresPerPixel, Point origin,
                                 const std::string& what);

}  // namespace fray::setup
