// fray_image_check IMAGE.png [MIN_WIDTH MIN_HEIGHT]: exits 0 when the image
// exists, has at least the given size and is neither blank nor uniform
// (many distinct colours, some spread of brightness). Used by the window tests.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fray/render/image.h"

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: fray_image_check IMAGE.png [MIN_WIDTH MIN_HEIGHT]\n");
        return 2;
    }
    auto img = fray::render::readPng(argv[1]);
    if (!img) {
        std::fprintf(stderr, "fray_image_check: %s\n", img.error().message.c_str());
        return 1;
    }
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
