#include "overlay_builder.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fray/render/font.h"

namespace fray::render {

namespace {
constexpr float kPi = 3.14159265358979f;
}

std::uint32_t packColor(glm::vec4 c) {
    auto b = [](float v) { return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return b(c.x) | (b(c.y) << 8) | (b(c.z) << 16) | (b(c.w) << 24);
}

Bounds characterBounds(std::span<const CharacterInstance> characters) {
    Bounds b;
    for (const CharacterInstance& c : characters)
        for (const glm::vec3& p : c.jointPositions) b.add(p);
    return b;
}

void OverlayBuilder::clear() {
    for (auto& g : groups_) g.clear();
}

std::size_t OverlayBuilder::vertexCount() const {
    return groups_[0].size() + groups_[1].size() + groups_[2].size();
}

void OverlayBuilder::triangle(OverlayGroup g, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec4 color) {
    const std::uint32_t col = packColor(color);
    auto& v = out(g);
    v.push_back({a, {0, 0}, col, 0});
    v.push_back({b, {0, 0}, col, 0});
    v.push_back({c, {0, 0}, col, 0});
}

void OverlayBuilder::writeQuad(OverlayVertex* at, glm::vec3 c, glm::vec3 r, glm::vec3 u, glm::vec4 color, OverlayMode mode) {
    const std::uint32_t col = packColor(color);
    const auto m = static_cast<std::uint32_t>(mode);
    const OverlayVertex v00{c - r - u, {-1, -1}, col, m};
    const OverlayVertex v10{c + r - u, {1, -1}, col, m};
    const OverlayVertex v11{c + r + u, {1, 1}, col, m};
    const OverlayVertex v01{c - r + u, {-1, 1}, col, m};
    at[0] = v00;
    at[1] = v10;
    at[2] = v11;
    at[3] = v00;
    at[4] = v11;
    at[5] = v01;
}

OverlayVertex* OverlayBuilder::appendQuads(OverlayGroup g, std::size_t count) {
    auto& v = out(g);
    const std::size_t first = v.size();
    v.resize(first + 6 * count);
    return v.data() + first;
}

void OverlayBuilder::quad(OverlayGroup g, glm::vec3 c, glm::vec3 r, glm::vec3 u, glm::vec4 color, OverlayMode mode) {
    writeQuad(appendQuads(g, 1), c, r, u, color, mode);
}

void OverlayBuilder::ribbon(OverlayGroup g, std::span<const glm::vec3> points, float width, glm::vec4 color, float lift) {
    if (points.size() < 2) return;
    const std::uint32_t col = packColor(color);
    const float half = width * 0.5f;
    auto side = [](glm::vec3 a, glm::vec3 b, glm::vec3& s) {
        glm::vec3 d = b - a;
        d.y = 0.0f;
        const float len = glm::length(d);
        if (len < 1e-6f) return false;
        s = glm::vec3(-d.z, 0.0f, d.x) / len;
        return true;
    };
    auto& v = out(g);
    glm::vec3 prevL(0.0f), prevR(0.0f);
    bool havePrev = false;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        glm::vec3 s;
        if (!side(points[i], points[i + 1], s)) continue;
        // Offset at the start of this segment: a miter with the previous
        // segment when there is one (limited so sharp turns do not spike).
        glm::vec3 s0 = s;
        glm::vec3 s1 = s;
        std::size_t j = i + 1;
        glm::vec3 sn;
        while (j + 1 < points.size() && !side(points[j], points[j + 1], sn)) ++j;
        if (j + 1 < points.size()) {
            glm::vec3 m = s + sn;
            const float ml = glm::length(m);
            if (ml > 1e-4f) {
                m /= ml;
                s1 = m / std::max(glm::dot(m, s), 0.5f);
            }
        }
        const glm::vec3 up(0.0f, lift, 0.0f);
        const glm::vec3 a = points[i] + up;
        const glm::vec3 b = points[i + 1] + up;
        const glm::vec3 aL = havePrev ? prevL : a + s0 * half;
        const glm::vec3 aR = havePrev ? prevR : a - s0 * half;
        const glm::vec3 bL = b + s1 * half;
        const glm::vec3 bR = b - s1 * half;
        v.push_back({aL, {0, 0}, col, 0});
        v.push_back({aR, {0, 0}, col, 0});
        v.push_back({bR, {0, 0}, col, 0});
        v.push_back({aL, {0, 0}, col, 0});
        v.push_back({bR, {0, 0}, col, 0});
        v.push_back({bL, {0, 0}, col, 0});
        prevL = bL;
        prevR = bR;
        havePrev = true;
    }
}

void OverlayBuilder::ring(OverlayGroup g, glm::vec3 c, float inner, float outer, glm::vec4 color, int segments) {
    const std::uint32_t col = packColor(color);
    auto& v = out(g);
    for (int i = 0; i < segments; ++i) {
        const float a0 = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(segments);
        const float a1 = 2.0f * kPi * static_cast<float>(i + 1) / static_cast<float>(segments);
        const glm::vec3 d0(std::cos(a0), 0.0f, std::sin(a0));
        const glm::vec3 d1(std::cos(a1), 0.0f, std::sin(a1));
        const OverlayVertex i0{c + d0 * inner, {0, 0}, col, 0};
        const OverlayVertex o0{c + d0 * outer, {0, 0}, col, 0};
        const OverlayVertex i1{c + d1 * inner, {0, 0}, col, 0};
        const OverlayVertex o1{c + d1 * outer, {0, 0}, col, 0};
        v.insert(v.end(), {i0, o0, o1, i0, o1, i1});
    }
}

void OverlayBuilder::rect(float x0, float y0, float x1, float y1, glm::vec4 color) {
    quad(OverlayGroup::Screen, glm::vec3((x0 + x1) * 0.5f, (y0 + y1) * 0.5f, 0.0f), glm::vec3((x1 - x0) * 0.5f, 0.0f, 0.0f),
         glm::vec3(0.0f, (y1 - y0) * 0.5f, 0.0f), color, OverlayMode::Solid);
}

void OverlayBuilder::text(float x, float y, std::string_view s, int scale, glm::vec4 color) {
    const std::uint32_t col = packColor(color);
    const auto mode = static_cast<std::uint32_t>(OverlayMode::Glyph);
    const float sc = static_cast<float>(scale);
    const float gw = font::kGlyphWidth * sc, gh = font::kGlyphHeight * sc;
    auto& v = out(OverlayGroup::Screen);
    float pen = std::floor(x);
    const float top = std::floor(y);
    for (char ch : s) {
        if (ch != ' ') {
            int cx = 0, cy = 0;
            font::atlasCell(ch, cx, cy);
            const float u0 = static_cast<float>(cx) / font::kAtlasWidth;
            const float v0 = static_cast<float>(cy) / font::kAtlasHeight;
            const float u1 = static_cast<float>(cx + font::kGlyphWidth) / font::kAtlasWidth;
            const float v1 = static_cast<float>(cy + font::kGlyphHeight) / font::kAtlasHeight;
            const OverlayVertex a{{pen, top, 0}, {u0, v0}, col, mode};
            const OverlayVertex b{{pen + gw, top, 0}, {u1, v0}, col, mode};
            const OverlayVertex c{{pen + gw, top + gh, 0}, {u1, v1}, col, mode};
            const OverlayVertex d{{pen, top + gh, 0}, {u0, v1}, col, mode};
            v.insert(v.end(), {a, b, c, a, c, d});
        }
        pen += font::kAdvance * sc;
    }
}

int autoTextScale(int viewportHeight) { return std::max(1, (viewportHeight + 180) / 360); }

namespace {

// A label box centred on x with its bottom edge at y (pixels).
void label(OverlayBuilder& out, float x, float y, std::string_view s, int scale, glm::vec4 background, glm::vec4 ink) {
    const float w = static_cast<float>(font::textWidth(s, scale));
    const float h = static_cast<float>(font::textHeight(scale));
    const float pad = 2.0f * static_cast<float>(scale);
    const float left = std::floor(x - w * 0.5f);
    const float top = std::floor(y - h - pad);
    out.rect(left - pad, top - pad, left + w + pad, top + h + pad, background);
    out.text(left, top, s, scale, ink);
}

}  // namespace

namespace {

bool covers(const PendingLabel& a, const PendingLabel& b) {
    const bool apartX = std::abs(a.x - b.x) >= a.halfWidth + b.halfWidth;
    const bool apartY = a.y <= b.y - b.height || b.y <= a.y - a.height;
    return !apartX && !apartY;
}

}  // namespace

// Labels of characters standing close together used to print over each other
// (see overlay_builder.h for the order).
void stackLabels(std::vector<PendingLabel>& labels) {
    // std::sort, not stable_sort: the latter allocates a buffer every frame.
    std::sort(labels.begin(), labels.end(), [](const PendingLabel& a, const PendingLabel& b) {
        if (a.selected != b.selected) return a.selected;
        if (a.y != b.y) return a.y > b.y;
        return a.index < b.index;
    });
    if (labels.size() > kMaxStackedLabels) return;
    for (std::size_t i = 1; i < labels.size(); ++i) {
        PendingLabel& l = labels[i];
        // l only moves up, and once above a box it never covers it again, so
        // this ends after at most i moves.
        for (bool moved = true; moved;) {
            moved = false;
            for (std::size_t k = 0; k < i; ++k) {
                if (!covers(l, labels[k])) continue;
                l.y = labels[k].y - labels[k].height - 1.0f;
                moved = true;
            }
        }
    }
}

void buildOverlays(const FrameDescription& frame, const glm::mat4& viewProj, glm::vec2 viewport, bool blobShadows,
                   OverlayBuilder& out, std::span<const Bounds> characterBounds) {
    out.clear();
    const RenderSettings& st = frame.settings;
    const OrbitCamera& cam = frame.camera;
    const glm::vec3 eye = cam.eye();
    const glm::vec3 camRight = cam.right();
    const glm::vec3 camUp = cam.up();
    const int scale = st.textScale > 0 ? st.textScale : autoTextScale(static_cast<int>(viewport.y));

    if (blobShadows) {
        // Under each character, pushed a little away from the sun and
        // stretched along its direction on the floor.
        glm::vec3 sun = frame.settings.lightDirection;
        sun.y = 0.0f;
        const float along = glm::length(sun);
        const glm::vec3 dir = along > 1e-4f ? sun / along : glm::vec3(0.0f, 0.0f, 1.0f);
        const glm::vec3 side(-dir.z, 0.0f, dir.x);
        const auto chars = frame.characters;
        std::size_t bodies = 0;
        for (const CharacterInstance& c : chars) bodies += c.jointPositions.empty() ? 0 : 1;
        OverlayVertex* const first = out.appendQuads(OverlayGroup::Depth, bodies);
        auto blob = [&](std::size_t i, std::size_t slot) {
            Bounds b;
            if (characterBounds.size() == chars.size()) {
                b = characterBounds[i];
            } else {
                for (const glm::vec3& p : chars[i].jointPositions) b.add(p);
            }
            const float r = 0.5f * std::max(b.max.x - b.min.x, b.max.z - b.min.z) + 0.22f;
            const float lift = std::clamp(b.min.y, 0.0f, 1.0f);  // fades as the body leaves the floor
            const glm::vec3 centre(b.center().x, 0.006f, b.center().z);
            OverlayBuilder::writeQuad(first + 6 * slot, centre + dir * (0.25f * r), dir * (1.35f * r), side * r,
                                      glm::vec4(0.0f, 0.0f, 0.0f, 0.5f * (1.0f - lift)), OverlayMode::Blob);
        };
        if (bodies == chars.size() && bodies >= 4096) {
            // A crowd: every character has a body, so slot i is character i.
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bodies, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t i = r.begin(); i != r.end(); ++i) blob(i, i);
            });
        } else {
            std::size_t slot = 0;
            for (std::size_t i = 0; i < chars.size(); ++i)
                if (!chars[i].jointPositions.empty()) blob(i, slot++);
        }
    }

    for (const Polyline& line : frame.trajectories) out.ribbon(OverlayGroup::Depth, line.points, line.width, line.color, 0.012f);

    for (const Checkpoint& cp : frame.checkpoints) {
        const glm::vec3 base(cp.position.x, 0.0f, cp.position.z);
        out.ring(OverlayGroup::Depth, base + glm::vec3(0, 0.014f, 0), cp.radius * 0.72f, cp.radius, cp.color);
        // A post facing the camera (turned about the vertical) with a pennant.
        glm::vec3 toEye = eye - base;
        toEye.y = 0.0f;
        const glm::vec3 side = glm::length(toEye) > 1e-4f ? glm::normalize(glm::vec3(toEye.z, 0.0f, -toEye.x)) : camRight;
        const float height = 1.1f;
        const glm::vec3 postHalfUp(0.0f, height * 0.5f, 0.0f);
        out.quad(OverlayGroup::Depth, base + postHalfUp, side * 0.018f, postHalfUp, cp.color, OverlayMode::Solid);
        const glm::vec3 top = base + glm::vec3(0.0f, height, 0.0f);
        out.triangle(OverlayGroup::Depth, top, top - glm::vec3(0.0f, 0.24f, 0.0f), top + side * 0.3f - glm::vec3(0.0f, 0.12f, 0.0f),
                     cp.color);
        if (st.labels && !cp.label.empty()) {
            if (auto px = projectToPixel(viewProj, top + glm::vec3(0.0f, 0.12f, 0.0f), viewport))
                if (px->z > 0.0f && px->z < 1.0f)
                    label(out, px->x, px->y, cp.label, scale, glm::vec4(0.1f, 0.1f, 0.1f, 0.6f), cp.color);
        }
    }

    std::vector<PendingLabel>& pending = out.scratchLabels();
    pending.clear();
    for (const CharacterInstance& c : frame.characters) {
        if (c.jointPositions.empty()) continue;
        if (c.selected) {
            Bounds b;
            for (const glm::vec3& p : c.jointPositions) b.add(p);
            const glm::vec3 centre(b.center().x, 0.012f, b.center().z);
            const float r = std::max(0.42f, 0.5f * std::max(b.max.x - b.min.x, b.max.z - b.min.z) + 0.18f);
            out.ring(OverlayGroup::Depth, centre, r * 0.82f, r, glm::vec4(st.highlightColor, 0.95f));
        }
        if (st.labels && !c.label.empty()) {
            glm::vec3 top = c.jointPositions[0];
            for (const glm::vec3& p : c.jointPositions)
                if (p.y > top.y) top = p;
            if (auto px = projectToPixel(viewProj, top + glm::vec3(0.0f, 0.22f, 0.0f), viewport)) {
                if (px->z > 0.0f && px->z < 1.0f) {
                    const float pad = 2.0f * static_cast<float>(scale);
                    pending.push_back({px->x, px->y, px->y, 0.5f * static_cast<float>(font::textWidth(c.label, scale)) + pad,
                                       static_cast<float>(font::textHeight(scale)) + 2.0f * pad, c.label, c.selected,
                                       static_cast<int>(pending.size())});
                }
            }
        }
    }
    stackLabels(pending);
    for (const PendingLabel& l : pending) {
        // A moved label hangs on a thin leader down to its character.
        if (l.y < l.anchorY - 0.5f)
            out.rect(std::floor(l.x) - 0.5f, l.y, std::floor(l.x) + 0.5f, l.anchorY, glm::vec4(0.9f, 0.9f, 0.9f, 0.7f));
        if (l.selected)
            label(out, l.x, l.y, l.text, scale, glm::vec4(st.highlightColor, 0.9f), glm::vec4(0.05f, 0.05f, 0.05f, 1.0f));
        else
            label(out, l.x, l.y, l.text, scale, glm::vec4(0.08f, 0.08f, 0.1f, 0.62f), glm::vec4(1.0f));
    }

    for (const Flash& f : frame.flashes)
        out.quad(OverlayGroup::OnTop, f.position, camRight * f.radius, camUp * f.radius, f.color, OverlayMode::Disc);
}

}  // namespace fray::render
