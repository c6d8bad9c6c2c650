// libFuzzer target for the BVH reader. Properties checked on every input:
// the reader never crashes, leaks or hangs, and whatever it accepts, the writer
// turns into text the reader accepts again with the same shape.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fray/io/bvh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fray::BvhReadOptions opt;
    opt.maxFrames = 100'000;
    opt.maxMotionBytes = std::size_t{64} << 20;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto motion = fray::readBvhFromMemory(text, "fuzz.bvh", opt);
    if (!motion) return 0;
    const std::string written = fray::writeBvhToString(*motion);
    auto again = fray::readBvhFromMemory(written, "rewritten.bvh", opt);
    if (!again || again->frameCount() != motion->frameCount() || again->jointCount() != motion->jointCount())
        std::abort();
    return 0;
}
