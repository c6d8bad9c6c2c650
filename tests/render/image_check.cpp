// fray_image_check: checks on the window tests' screenshots.
//
//   fray_image_check IMAGE.png [MIN_WIDTH MIN_HEIGHT]
//       exits 0 when the image exists, has at least the given size and is
//       neither blank nor uniform (many distinct colours, some spread of
//       brightness).
//   fray_image_check IMAGE.png --tint R,G,B MIN_PIXELS
//       exits 0 when at least MIN_PIXELS pixels have the hue of the display
//       colour R,G,B (0..1, a character's tint) under any light: shaded bodies
//       of that tint are in the picture.
//   fray_image_check IMAGE.png --differs OTHER.png MIN_PIXELS [R,G,B]
//       exits 0 when at least MIN_PIXELS pixels differ by more than 8 levels
//       between the two images (of one size), counting with R,G,B only those
//       of that hue in either image: something of that tint moved.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fray/render/image.h"

namespace {

using Rgb = std::array<double, 3>;

bool parseRgb(const char* s, Rgb& out) {
    return std::sscanf(s, "%lf,%lf,%lf", &out[0], &out[1], &out[2]) == 3 && out[0] + out[1] + out[2] > 0.0;
}

// Same hue as the tint: the pixel's chromaticity (colour over its sum) within
// 0.06 of the tint's in every channel, and not too dark to tell. The grey
// floor, the bluish fog and the black-and-white labels never pass for the
// team colours.
bool hasTint(const std::uint8_t* p, const Rgb& tint) {
    const double sum = double(p[0]) + double(p[1]) + double(p[2]);
    if (sum < 90.0) return false;
    const double tsum = tint[0] + tint[1] + tint[2];
    for (int k = 0; k < 3; ++k)
        if (std::abs(double(p[k]) / sum - tint[static_cast<std::size_t>(k)] / tsum) > 0.06) return false;
    return true;
}

fray::Result<fray::render::Image> load(const char* path) {
    auto img = fray::render::readPng(path);
    if (!img) std::fprintf(stderr, "fray_image_check: %s\n", img.error().message.c_str());
    return img;
}

int usage() {
    std::fprintf(stderr,
                 "usage: fray_image_check IMAGE.png [MIN_WIDTH MIN_HEIGHT]\n"
                 "       fray_image_check IMAGE.png --tint R,G,B MIN_PIXELS\n"
                 "       fray_image_check IMAGE.png --differs OTHER.png MIN_PIXELS [R,G,B]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage();
    auto img = load(argv[1]);
    if (!img) return 1;
    const std::string mode = argc > 2 ? argv[2] : "";

    if (mode == "--tint") {
        Rgb tint{};
        if (argc != 5 || !parseRgb(argv[3], tint)) return usage();
        const long wanted = std::atol(argv[4]);
        long n = 0;
        for (int y = 0; y < img->height; ++y)
            for (int x = 0; x < img->width; ++x) n += hasTint(img->pixel(x, y), tint) ? 1 : 0;
        std::printf("%s: %ld pixels of the tint %s (at least %ld wanted)\n", argv[1], n, argv[3], wanted);
        return n >= wanted ? 0 : 1;
    }

    if (mode == "--differs") {
        Rgb tint{};
        if ((argc != 5 && argc != 6) || (argc == 6 && !parseRgb(argv[5], tint))) return usage();
        auto other = load(argv[3]);
        if (!other) return 1;
        if (other->width != img->width || other->height != img->height) {
            std::fprintf(stderr, "fray_image_check: %s is %dx%d, %s is %dx%d\n", argv[1], img->width, img->height, argv[3],
                         other->width, other->height);
            return 1;
        }
        const long wanted = std::atol(argv[4]);
        long n = 0;
        for (int y = 0; y < img->height; ++y)
            for (int x = 0; x < img->width; ++x) {
                const std::uint8_t* a = img->pixel(x, y);
                const std::uint8_t* b = other->pixel(x, y);
                bool differs = false;
                for (int k = 0; k < 3; ++k) differs = differs || std::abs(int(a[k]) - int(b[k])) > 8;
                if (differs && (argc == 5 || hasTint(a, tint) || hasTint(b, tint))) ++n;
            }
        std::printf("%s vs %s: %ld differing pixels%s%s (at least %ld wanted)\n", argv[1], argv[3], n,
                    argc == 6 ? " of the tint " : "", argc == 6 ? argv[5] : "", wanted);
        return n >= wanted ? 0 : 1;
    }

    if (argc == 3 || argc > 4) return usage();
    const int minW = argc > 3 ? std::atoi(argv[2]) : 1;
    const int minH = argc > 3 ? std::atoi(argv[3]) : 1;
    const auto st = fray::render::imageStats(*img);
    std::printf("%s: %dx%d, %d distinct colours, luma mean %.1f, sd %.1f\n", argv[1], img->width, img->height,
                st.distinctColors, st.meanLuma, st.lumaStdDev);
    if (img->width < minW || img->height < minH) {
        std::fprintf(stderr, "fray_image_check: %s is %dx%d, expected at least %dx%d\n", argv[1], img->width, img->height, minW, minH);
        return 1;
    }
    if (st.distinctColors < 64 || st.lumaStdDev < 8.0) {
        std::fprintf(stderr, "fray_image_check: %s looks blank or uniform\n", argv[1]);
        return 1;
    }
    return 0;
}
