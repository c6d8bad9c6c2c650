#include "fray/render/image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstring>
#include <fstream>
#include <string>
#include <unordered_set>

#include "fray/core/atomic_file.h"
#include "fray/render/font.h"

namespace fray::render {

void Image::resize(int w, int h) {
    width = std::max(0, w);
    height = std::max(0, h);
    rgba.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
}

namespace {

// libpng reports errors through longjmp; these keep the message for the Error.
struct PngErrorState {
    std::string message;
};

void pngError(png_structp png, png_const_charp msg) {
    auto* st = static_cast<PngErrorState*>(png_get_error_ptr(png));
    if (st) st->message = msg;
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

void pngWriteToString(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::string*>(png_get_io_ptr(png));
    out->append(reinterpret_cast<const char*>(data), length);
}

void pngFlush(png_structp) {}

struct ReadCursor {
    const std::string* data;
    std::size_t pos;
};

void pngReadFromString(png_structp png, png_bytep out, png_size_t length) {
    auto* cur = static_cast<ReadCursor*>(png_get_io_ptr(png));
    if (cur->pos + length > cur->data->size()) png_error(png, "file ends early");
    std::memcpy(out, cur->data->data() + cur->pos, length);
    cur->pos += length;
}

// Encodes into memory so the file can be written atomically. Kept free of
// C++ objects with destructors between setjmp and the libpng calls.
bool encodePng(const Image& image, std::string& out, PngErrorState& err) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, pngError, pngWarning);
    if (!png) {
        err.message = "out of memory";
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &out, pngWriteToString, pngFlush);
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    for (int y = 0; y < image.height; ++y) png_write_row(png, const_cast<png_bytep>(image.pixel(0, y)));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

// rows lives in the caller so a longjmp out of libpng leaves no C++ object
// of this frame half-updated.
bool decodePng(const std::string& data, Image& image, std::vector<png_bytep>& rows, PngErrorState& err) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, pngError, pngWarning);
    if (!png) {
        err.message = "out of memory";
        return false;
    }
    png_infop info = png_create_info_struct(png);
    ReadCursor cursor{&data, 0};
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_set_read_fn(png, &cursor, pngReadFromString);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info);
    const png_uint_32 h = png_get_image_height(png, info);
    if (w == 0 || h == 0 || w > 16384 || h > 16384) png_error(png, "image size out of range (1..16384)");
    png_set_expand(png);
    png_set_strip_16(png);
    png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != static_cast<png_size_t>(w) * 4) png_error(png, "unsupported pixel layout");
    image.resize(static_cast<int>(w), static_cast<int>(h));
    rows.resize(h);
    for (png_uint_32 y = 0; y < h; ++y) rows[y] = image.pixel(0, static_cast<int>(y));
    png_read_image(png, rows.data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

}  // namespace

Status writePng(const std::filesystem::path& path, const Image& image) {
    if (image.empty() || image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
        return makeError(path.string() + ": cannot write an empty or inconsistent image");
    std::string bytes;
    bytes.reserve(image.rgba.size() / 2);
    PngErrorState err;
    if (!encodePng(image, bytes, err)) return makeError(path.string() + ": PNG encoding failed: " + err.message);
    return writeFileAtomically(path, bytes);
}

Result<Image> readPng(const std::filesystem::path& path) {
    auto data = readWholeFile(path, "the PNG image");
    if (!data) return data.error();
    if (data->size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(data->data()), 0, 8) != 0)
        return makeError(path.string() + ": not a PNG file");
    Image image;
    std::vector<png_bytep> rows;
    PngErrorState err;
    if (!decodePng(*data, image, rows, err)) return makeError(path.string() + ": bad PNG: " + err.message);
    return image;
}

void blit(const Image& src, Image& dst, int x, int y) {
    const int x0 = std::max(0, x), y0 = std::max(0, y);
    const int x1 = std::min(dst.width, x + src.width), y1 = std::min(dst.height, y + src.height);
    if (x1 <= x0) return;
    for (int row = y0; row < y1; ++row)
        std::memcpy(dst.pixel(x0, row), src.pixel(x0 - x, row - y), static_cast<std::size_t>(x1 - x0) * 4);
}

void drawText(Image& image, int x, int y, std::string_view text, int scale, const std::uint8_t rgba[4], bool box) {
    auto put = [&](int px, int py, const std::uint8_t c[4], int alpha) {
        if (px < 0 || py < 0 || px >= image.width || py >= image.height) return;
        std::uint8_t* p = image.pixel(px, py);
        for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>((c[k] * alpha + p[k] * (255 - alpha)) / 255);
    };
    if (box) {
        const std::uint8_t dark[4] = {20, 20, 24, 255};
        const int pad = 2 * scale;
        const int w = font::textWidth(text, scale), h = font::textHeight(scale);
        for (int py = y - pad; py < y + h + pad; ++py)
            for (int px = x - pad; px < x + w + pad; ++px) put(px, py, dark, 160);
    }
    int pen = x;
    for (char ch : text) {
        for (int gy = 0; gy < font::kGlyphHeight; ++gy)
            for (int gx = 0; gx < font::kGlyphWidth; ++gx)
                if (font::glyphPixel(ch, gx, gy))
                    for (int sy = 0; sy < scale; ++sy)
                        for (int sx = 0; sx < scale; ++sx) put(pen + gx * scale + sx, y + gy * scale + sy, rgba, rgba[3]);
        pen += font::kAdvance * scale;
    }
}

ImageDiff compareImages(const Image& a, const Image& b, int threshold) {
    ImageDiff d;
    if (a.width != b.width || a.height != b.height) {
        d.sizeMismatch = true;
        d.total = std::max(a.width * a.height, 1);
        d.differing = d.total;
        return d;
    }
    d.total = a.width * a.height;
    d.minX = a.width;
    d.minY = a.height;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::uint8_t* p = a.pixel(x, y);
            const std::uint8_t* q = b.pixel(x, y);
            int delta = 0;
            for (int c = 0; c < 4; ++c) delta = std::max(delta, std::abs(int(p[c]) - int(q[c])));
            d.maxDelta = std::max(d.maxDelta, delta);
            if (delta > threshold) {
                ++d.differing;
                d.minX = std::min(d.minX, x);
                d.minY = std::min(d.minY, y);
                d.maxX = std::max(d.maxX, x);
                d.maxY = std::max(d.maxY, y);
            }
        }
    }
    if (d.differing == 0) d.minX = d.minY = 0;
    return d;
}

Image diffImage(const Image& a, const Image& b, int threshold) {
    Image out;
    out.resize(a.width, a.height);
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::uint8_t* p = a.pixel(x, y);
            std::uint8_t* o = out.pixel(x, y);
            const auto grey = static_cast<std::uint8_t>((p[0] + p[1] + p[2]) / 6 + 40);
            bool differs = b.width != a.width || b.height != a.height;
            if (!differs) {
                const std::uint8_t* q = b.pixel(x, y);
                for (int c = 0; c < 4; ++c) differs = differs || std::abs(int(p[c]) - int(q[c])) > threshold;
            }
            o[0] = differs ? 255 : grey;
            o[1] = differs ? 0 : grey;
            o[2] = differs ? 0 : grey;
            o[3] = 255;
        }
    }
    return out;
}

ImageStats imageStats(const Image& image, int cap) {
    ImageStats s;
    if (image.empty()) return s;
    std::unordered_set<std::uint32_t> colors;
    double sum = 0, sum2 = 0;
    const double n = static_cast<double>(image.width) * image.height;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.pixel(x, y);
            if (static_cast<int>(colors.size()) < cap) colors.insert(std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16);
            const double l = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            sum += l;
            sum2 += l * l;
        }
    }
    s.distinctColors = static_cast<int>(colors.size());
    s.meanLuma = sum / n;
    s.lumaStdDev = std::sqrt(std::max(0.0, sum2 / n - s.meanLuma * s.meanLuma));
    return s;
}

}  // namespace fray::render
